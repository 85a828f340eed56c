"""Rules of a parsed grammar (ggg.Grammar.rules: dicts with name, symbol, vertices, edges,
nonterminals, embedding points, level and uses)."""


def rule_of(parsed, identifier):
    """The rule dict whose symbol name (or number) is ``identifier``, else None."""
    for rule in parsed.rules:
        if rule["name"] == identifier or str(rule["symbol"]) == identifier:
            return rule
    return None


def describe_rule(rule):
    return "{} -> {} vertices, {} edges, {} nonterminals, {} embedding points".format(
        rule["name"], rule["vertices"], rule["edges"], rule["nonterminals"], rule["embedding_points"])


def looks_like_grammar_file(head):
    """Whether the beginning of a text names the grammar file format."""
    return '"ggg-grammar"' in head
