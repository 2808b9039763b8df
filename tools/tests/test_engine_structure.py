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


def test_kind_enumerators_and_tests():
    text = "/* c */ typedef enum pdt_model_kind { PDT_MODEL_FOPDT = 1, PDT_MODEL_SOPDT = 2 } " \
           "pdt_model_kind_t;"
    names = ces.kind_enumerators(text)
    assert names == ["PDT_MODEL_FOPDT", "PDT_MODEL_SOPDT"]
    pat = ces.kind_test_pattern(names)
    counted = ["m->kind == PDT_MODEL_FOPDT", "PDT_MODEL_SOPDT != k", "k == PDT_MODEL_FOPDT ? 1 : 2",
               "(PDT_MODEL_FOPDT) == k", "k > PDT_MODEL_FOPDT", "case PDT_MODEL_SOPDT:"]
    ignored = ["m->kind = PDT_MODEL_FOPDT;", "x ? PDT_MODEL_FOPDT : PDT_MODEL_SOPDT",
               "f(PDT_MODEL_SOPDT);", "k == PDT_MODEL_PARAM_TD", "#ifndef PDT_MODEL_H"]
    assert [len(pat.findall(s)) for s in counted] == [1] * len(counted)
    assert [len(pat.findall(s)) for s in ignored] == [0] * len(ignored)


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_wswitch_names_every_layer_switch(tmp_path):
    """A new enumerator of pdt_model_kind_t: -Wswitch names every switch of
    the layer (none has a default), and the layer has a switch per
    operation only (kind_tests keeps kinds out of the other files)."""
    import re
    import subprocess
    inc = tmp_path / "include"
    shutil.copytree(ROOT / "lib" / "include", inc)
    header = inc / "pdt" / "pdt_model.h"
    text = header.read_text()
    new = text.replace("PDT_MODEL_SOPDT = 2 }", "PDT_MODEL_SOPDT = 2, PDT_MODEL_NEW = 3 }")
    assert new != text
    header.write_text(new)
    src = ROOT / "lib" / "src" / "pdt_model.c"
    res = subprocess.run(["cc", "-std=c99", "-Wswitch", "-c", "-I", str(inc), "-I",
                          str(src.parent), str(src), "-o", str(tmp_path / "m.o")],
                         capture_output=True, text=True, check=True)
    named = set(re.findall(r"(pdt_model\.c|pdt_model_priv\.h):(\d+):\d+: warning: "
                           r"enumeration value .PDT_MODEL_NEW", res.stderr))
    switches = sum(len(re.findall(r"\bswitch\s*\(", ces.strip_comments((src.parent / f).read_text())))
                   for f in ces.KIND_LAYER)
    assert switches > 0 and len(named) == switches


def test_state_phase_pattern():
    pat = ces.STATE_PHASE
    counted = ["c->coarse.stage == 2u", "if (p->stage != 4u) {", "nm->kink == 1u ||",
               "c->rest_stage == 1u)", "s.mode == 3"]
    ignored = ["c->cfg.coarse == 1u", "cfg->coarse == 1u", "c->vote.done == 0u",
               "++s->i == 2u * PDT_IDENT_SCAN_POINTS", "k == 1u", "x->f == 1.5",
               "c->nm.start_i >= c->nm.nstarts", "v.lags == 1u", "view->lags != 2u"]
    assert [len(pat.findall(s)) for s in counted] == [1] * len(counted)
    assert [len(pat.findall(s)) for s in ignored] == [0] * len(ignored)


def test_union_member_pattern():
    pat = ces.UNION_MEMBER
    counted = ["m->p.fopdt.tau", "m.p.sopdt.b = 0", "x->model.p . sopdt"]
    ignored = ["p.fopdt_like", "v.tau", "map.sopdt", "pdt_model_fopdt_t"]
    assert [len(pat.findall(s)) for s in counted] == [1] * len(counted)
    assert [len(pat.findall(s)) for s in ignored] == [0] * len(ignored)
