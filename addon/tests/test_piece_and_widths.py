"""core.piece (Replace's stored piece) and core.widths."""

import numpy as np
import pytest

from road_grammar.core import widths
from road_grammar.core.piece import DEFAULT_CLASS, Piece, PieceError, class_names


def test_piece_round_trip_and_size():
    piece = Piece([[0, 0], [30, 0], [30, 20]], [[0, 1], [1, 2]], ["primary", "residential"], "town (selection)")
    assert piece.vertex_count == 3 and piece.edge_count == 2 and piece.size() == (30.0, 20.0)
    assert piece.problem() is None
    again = Piece.from_json(piece.to_json())
    np.testing.assert_array_equal(again.positions, piece.positions)
    assert again.edges.tolist() == piece.edges.tolist() and again.highway == piece.highway
    assert again.source == "town (selection)"


@pytest.mark.parametrize("positions, edges, problem", [
    ([], [], "no vertices"), ([[0, 0], [1, 0]], [], "no streets"),
    ([[0, 0], [np.inf, 0]], [[0, 1]], "not finite"), ([[5, 5], [5, 5]], [[0, 1]], "no size"),
])
def test_piece_problems(positions, edges, problem):
    assert problem in Piece(positions, edges, ["road"] * len(edges)).problem()


def test_piece_from_bad_json():
    with pytest.raises(PieceError, match="cannot be read"):
        Piece.from_json("{")
    with pytest.raises(PieceError, match="cannot be read"):
        Piece.from_json('{"positions": [[0, 0, 0]], "edges": []}')
    with pytest.raises(PieceError):
        Piece([[0, 0], [1, 0]], [[0, 1]], [])
    assert Piece.from_json('{"positions": [[0, 0], [1, 0]], "edges": [[0, 1]]}').highway == [DEFAULT_CLASS]


class Classes:
    @staticmethod
    def highway_classes():
        return ["motorway", "primary", "residential"]


def test_piece_class_codes():
    piece = Piece([[0, 0], [1, 0]], [[0, 1]], ["primary"])
    assert piece.highway_codes(Classes).tolist() == [1]
    with pytest.raises(PieceError, match="footway"):
        Piece([[0, 0], [1, 0]], [[0, 1]], ["footway"]).highway_codes(Classes)
    assert class_names(Classes, None, 2) == [DEFAULT_CLASS] * 2
    assert class_names(Classes, [0, 2, 9, -1], 4) == ["motorway", "residential", "residential", "motorway"]


def test_class_default_widths():
    result = widths.class_default_widths([0, 1, 7], {"motorway": 12.0}, ["motorway", "path"])
    assert result.tolist() == [12.0, 6.0, 6.0]
    assert widths.class_default_widths([0, 1], {}, []).tolist() == [6.0, 6.0]
