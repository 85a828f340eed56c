"""A learned grammar on its road graph (inverse procedural modelling, paper 6): kept as the
result of the object's last Learn (``object.road_learning``, properties.learning). It is
shown level by level by display.rules (``show_learned``).
"""

import json

import bpy

from ..core.names import LEARNED_FROM_KEY
from ..core.palette import rule_slot
from ..core.updates import suspended_updates


def text_for(obj):
    """The Text to hold a new grammar learned from ``obj``: the one of its last Learn (so
    learning again refreshes it), else a new one named after it."""
    text = obj.road_learning.text
    if text is not None and text.get(LEARNED_FROM_KEY) is not None:
        return text
    return bpy.data.texts.new("{}.grammar.json".format(obj.name))


def store(context, obj, parsed, content, stats, parameters, seconds, topology):
    """Keep a learned grammar (``parsed``, its text ``content``, the ``stats`` of
    ggg.learn) as the result of ``obj`` and as the scene's grammar, the top level shown.
    Returns the Text."""
    text = text_for(obj)
    text.from_string(content)
    text[LEARNED_FROM_KEY] = obj.name
    text.use_fake_user = True
    context.scene.road_grammar.text = text
    result = obj.road_learning
    with suspended_updates():
        result.text = text
        result.stats = json.dumps(stats, sort_keys=True)
        result.parameters = parameters
        result.mode = parsed.mode
        result.levels = int(parsed.levels)
        result.seconds = float(seconds)
        result.topology = topology.checksum
        result.rules.clear()
        result.active_rule = -1
        for index, rule in enumerate(parsed.rules):
            item = result.rules.add()
            item.name = rule["name"]
            item.symbol = int(rule["symbol"])
            item.level = int(rule["level"])
            item.uses = int(rule["uses"])
            item.vertex_count = int(rule["vertices"])
            item.edge_count = int(rule["edges"])
            item.nonterminals = int(rule["nonterminals"])
            item.embedding_points = int(rule["embedding_points"])
            item.color_slot = rule_slot(index)
        result.level = result.levels
    return text
