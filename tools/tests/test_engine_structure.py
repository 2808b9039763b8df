"""tools/check_engine_structure.py: its cycle finder on known graphs, and its
figures on the checkout within their limits."""
import importlib.util
import pathlib
import shutil

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("ces", ROOT / "tools" / "check_engine_structure.py")
ces = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ces)


def test_cycles_of_known_graphs():
    assert ces.cycles({"a": ["b"], "b": ["c"], "c": []}) == []
    assert ces.cycles({"a": ["b"], "b": ["a"], "c": ["a"]}) == [["a", "b"]]
    g = {"a": ["b"], "b": ["c"], "c": ["a", "d"], "d": ["e"], "e": ["d"], "f": []}
    assert sorted(ces.cycles(g)) == [["a", "b", "c"], ["d", "e"]]


def test_graph_from_symbols():
    syms = {"x.c": ({"f"}, {"g", "printf"}), "y.c": ({"g"}, {"f"}), "z.c": (set(), {"g"})}
    assert ces.graph(syms) == {"x.c": ["y.c"], "y.c": ["x.c"], "z.c": ["y.c"]}


@pytest.mark.skipif(shutil.which("cc") is None or shutil.which("nm") is None,
                    reason="no C compiler or nm")
def test_checkout_within_limits():
    figures, _ = ces.measure("cc")
    limits = ces.read_limits()
    assert set(figures) == set(limits)
    assert all(figures[k] <= limits[k] for k in figures)
