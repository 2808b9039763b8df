"""tools/engine_plan.py: the plan it reads from the sequencer, and the
section of docs/ident-engine.md it writes, current on the checkout."""
import importlib.util
import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("engine_plan", ROOT / "tools" / "engine_plan.py")
engine_plan = importlib.util.module_from_spec(spec)
spec.loader.exec_module(engine_plan)


def test_every_phase_has_a_row_a_stage_and_a_way_on():
    code = engine_plan.SEQUENCER.read_text()
    priv = engine_plan.PRIV.read_text()
    phases = [p for p, _ in engine_plan.enum_comments(priv, "PH_")
              if p not in ("PH_DONE", "PH_COUNT")]
    rows = {ph: nexts for ph, _, nexts in engine_plan.plan(code)}
    stages = engine_plan.stages(code)
    assert sorted(rows) == sorted(phases)
    assert sorted(stages) == sorted(phases)
    outcomes = {o for o, _ in engine_plan.enum_comments(priv, "OUT_")}
    for ph, nexts in rows.items():
        assert nexts, ph
        for out, nxt in nexts:
            assert out in outcomes and (nxt in phases or nxt == "PH_DONE"), (ph, out, nxt)


def test_every_phase_is_reached():
    """From the first phase (init's, or the one its stage leads to) every
    phase is reached, and PH_DONE."""
    rows = {ph: nexts for ph, _, nexts in engine_plan.plan(engine_plan.SEQUENCER.read_text())}
    first = engine_plan.enum_comments(engine_plan.PRIV.read_text(), "PH_")[0][0]
    reached = {first, "PH_GA_START"}
    todo = [first, "PH_GA_START"]
    while todo:
        for _, nxt in rows.get(todo.pop(), []):
            if nxt not in reached:
                reached.add(nxt)
                todo.append(nxt)
    assert reached == set(rows) | {"PH_DONE"}


def test_needs_in_words():
    defs = engine_plan.macros("#define NEEDS_BUDGET 1u\n#define EVALUATES 2u\n"
                              "#define NEEDS_EVAL (NEEDS_BUDGET | EVALUATES)\n")
    assert engine_plan.needs_words("NEEDS_EVAL", defs) == "budget, evaluates"
    assert engine_plan.needs_words("0u", defs) == engine_plan.FREE


def test_document_is_current():
    assert engine_plan.stale() is None
    doc = engine_plan.DOC.read_text()
    assert len(re.findall(re.escape(engine_plan.BEGIN), doc)) == 1
