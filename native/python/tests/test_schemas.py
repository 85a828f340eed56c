"""The JSON Schemas of docs/schemas hold for the files ggg writes: grammars hand-written (version 1)
and learned (the packed version 6, both modes), and .ggraph graphs; and they refuse a packed
grammar laid out otherwise."""
import copy
import json
from pathlib import Path

import pytest

import ggg

jsonschema = pytest.importorskip("jsonschema", reason="the Python package jsonschema (Debian: python3-jsonschema) checks the schemas")

REPO = Path(__file__).resolve().parents[3]
SCHEMAS = REPO / "docs" / "schemas"
SAMPLE_CITY = REPO / "samples" / "sample_city.osm"
SIERPINSKI = REPO / "samples" / "sierpinski.grammar.json"


def validator(name):
    schema = json.loads((SCHEMAS / name).read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def test_hand_written_and_learned_grammars_pass_the_grammar_schema(tmp_path):
    check = validator("grammar.schema.json")
    check.validate(json.loads(SIERPINSKI.read_text()))
    written = tmp_path / "sierpinski.json"
    ggg.read_grammar(str(SIERPINSKI)).write(str(written))
    doc = json.loads(written.read_text())
    assert doc["version"] == 1
    check.validate(doc)
    town = ggg.read_graph(str(SAMPLE_CITY))
    for lossless in (False, True):
        path = tmp_path / f"town_{lossless}.json"
        grammar, _ = ggg.learn(town, lossless=lossless)
        grammar.write(str(path))
        doc = json.loads(path.read_text())
        assert doc["version"] == 6
        check.validate(doc)
    # The packed form's layout is checked: a section with a column too many, a column that is
    # not an array, a setting of the wrong type, an exponent out of range.
    damaged = []
    for edit in (lambda d: d["rules"].append([]) if len(d["rules"]) == 11 else d["rules"].extend([[]] * (12 - len(d["rules"]))),
                 lambda d: d["axiom"].__setitem__(0, 5),
                 lambda d: d["encoding"].__setitem__(0, "zip"),
                 lambda d: d["encoding"].__setitem__(2, "wide"),
                 lambda d: d["axiom"][5].__setitem__(0, 9)):
        bad = copy.deepcopy(doc)
        edit(bad)
        damaged.append(bad)
    for bad in damaged:
        with pytest.raises(jsonschema.ValidationError):
            check.validate(bad)


def test_written_graphs_pass_the_graph_schema(tmp_path):
    check = validator("ggraph.schema.json")
    path = tmp_path / "town.ggraph"
    ggg.read_graph(str(SAMPLE_CITY)).write(str(path))
    check.validate(json.loads(path.read_text()))
