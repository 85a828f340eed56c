"""Grammar texts: a Text datablock holds a grammar file (ggg-grammar JSON, see
docs/file-formats.md), so that it is saved inside the .blend; the scene's grammar is
``scene.road_grammar.text`` (properties.grammar).

The text is parsed by the native module (ggg.parse_grammar) when it is used; the last
parse is cached by content, so the sidebar and the rule menus do not parse on every redraw,
and an edit of the text in the Text Editor is seen at once.
"""

import bpy

from ..core import native
from ..core.grammar import describe_rule, looks_like_grammar_file
from ..core.names import LEARNED_FROM_KEY, SOURCE_KEY


class GrammarUnavailable(Exception):
    """No grammar can be used: none is loaded, or its text does not parse. The message
    says which."""


# Text name -> (content, ggg.Grammar or the error), for the last few texts parsed (the
# scene's grammar, the one Place Rule uses, the two of Stitch Cities).
_cache = {}
_CACHED_TEXTS = 8


def parse_text(text):
    """The ggg.Grammar of a Text datablock; raises ggg.GrammarError (or NativeModuleError)."""
    ggg = native.load()
    content = text.as_string()
    cached = _cache.get(text.name_full)
    if cached is not None and cached[0] == content:
        result = cached[1]
    else:
        try:
            result = ggg.parse_grammar(content, text.name_full)
        except ggg.Error as ex:
            result = ex
        _cache.pop(text.name_full, None)
        while len(_cache) >= _CACHED_TEXTS:
            _cache.pop(next(iter(_cache)))
        _cache[text.name_full] = (content, result)
    if isinstance(result, Exception):
        raise result
    return result


def of_text(text):
    """(Text, ggg.Grammar) of a grammar Text; raises GrammarUnavailable or
    native.NativeModuleError."""
    ggg = native.load()
    try:
        return text, parse_text(text)
    except ggg.Error as ex:
        raise GrammarUnavailable("The grammar text '{}' is not a valid grammar: {}".format(text.name, ex)) from ex


def named(name):
    """(Text, ggg.Grammar) of the Text ``name``; raises GrammarUnavailable (no such text,
    not a grammar) or native.NativeModuleError."""
    text = bpy.data.texts.get(name)
    if text is None:
        raise GrammarUnavailable("No text named '{}' holds a grammar".format(name))
    return of_text(text)


def looks_like_grammar(text):
    """Whether a Text looks like a grammar file (its beginning names the format), without
    parsing it: what the grammar pickers list."""
    if text is None or text.name.startswith("."):
        return False
    if text.get(SOURCE_KEY) is not None or text.get(LEARNED_FROM_KEY) is not None:
        return True
    return looks_like_grammar_file("".join(line.body for line in text.lines[:4])[:400])


def learned_text(obj):
    """The grammar Text learned from the road graph ``obj`` (its Learn result), else None."""
    result = getattr(obj, "road_learning", None)
    return result.text if result is not None else None


def active_text(context):
    settings = getattr(context.scene, "road_grammar", None)
    return settings.text if settings is not None else None


def active(context):
    """(Text, ggg.Grammar) of the scene's active grammar; raises GrammarUnavailable or
    native.NativeModuleError."""
    text = active_text(context)
    if text is None:
        raise GrammarUnavailable("No grammar in this scene: load one (Roads sidebar > Grammar > Load)")
    return of_text(text)


def chosen_text(owner, context):
    """The grammar Text a rule menu lists: the one its owner names (Place Rule's
    ``grammar``, the panel's ``place_grammar``), else the scene's."""
    name = getattr(owner, "grammar", None)
    if isinstance(name, str) and name:
        return bpy.data.texts.get(name)
    picked = getattr(owner, "place_grammar", None)
    if isinstance(picked, bpy.types.Text):
        return picked
    return active_text(context)


def try_active(context):
    """(Text or None, grammar or None, message or None), for drawing: never raises."""
    try:
        text, parsed = active(context)
        return text, parsed, None
    except (GrammarUnavailable, native.NativeModuleError) as ex:
        return active_text(context), None, str(ex)


def city_grammar_text(context, obj, fallback_to_scene):
    """The grammar Text of a city: the one learned from its road graph, else (for the
    active city) the scene's grammar."""
    text = learned_text(obj)
    if text is None and fallback_to_scene:
        text = active_text(context)
    return text


# Blender needs the strings of dynamic enum items to stay alive while it shows them.
_rule_items = []


def rule_items(_self, context):
    """Enum items of the active grammar's rules: (symbol name, "name (k)", description)."""
    items = []
    parsed = None
    if context is not None:
        text = chosen_text(_self, context)
        try:
            parsed = of_text(text)[1] if text is not None else None
        except (GrammarUnavailable, native.NativeModuleError):
            parsed = None
    if parsed is not None:
        # Values by position, so that the default (0) is the first rule of any grammar.
        for index, rule in enumerate(parsed.rules):
            items.append((rule["name"], "{} ({})".format(rule["name"], rule["symbol"]), describe_rule(rule), index))
    if not items:
        items.append(('NONE', "No Rules", "Load a grammar first", 0))
    _rule_items[:] = items
    return _rule_items


def forget():
    """Drop the parsed grammars kept in memory (the add-on is being disabled)."""
    _cache.clear()
