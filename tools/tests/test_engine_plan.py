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
              if p not in ("PH_DONE", engine_plan.RETURN, "PH_COUNT")]
    rows = {ph: nexts for ph, _, nexts in engine_plan.plan(code)}
    stages = engine_plan.stages(code)
    assert sorted(rows) == sorted(phases)
    assert sorted(stages) == sorted(phases)
    outcomes = {o for o, _ in engine_plan.enum_comments(priv, "OUT_")}
    for ph, nexts in rows.items():
        assert nexts, ph
        for out, nxt in nexts:
            assert out in outcomes and (nxt in phases or nxt in ("PH_DONE", engine_plan.RETURN)), \
                (ph, out, nxt)
    for ph, _, ways in engine_plan.plan_ways(code):
        for out, nxt, then in ways:
            assert not then or (then in phases and nxt != engine_plan.RETURN), (ph, out, then)


def test_every_return_is_named_before_it_is_taken():
    """PH_RETURN is reached only inside a search or a polish: from init's
    phase (PH_SHAPE_BEGIN, lib/src/pdt_ident.c's start), every path to a phase
    whose way is PH_RETURN passes a way that names the phase to return to
    (a walk that carries the phase named last, None before any)."""
    code = engine_plan.SEQUENCER.read_text()
    assert "c->phase = PH_SHAPE_BEGIN;" in code
    ways = {ph: w for ph, _, w in engine_plan.plan_ways(code)}
    seen = set()
    todo = [("PH_SHAPE_BEGIN", None)]
    while todo:
        ph, then = todo.pop()
        if (ph, then) in seen or ph == "PH_DONE":
            continue
        seen.add((ph, then))
        for _, nxt, named in ways[ph]:
            if nxt == engine_plan.RETURN:
                assert then is not None, ph
                todo.append((then, then))
            else:
                todo.append((nxt, named or then))


def test_every_phase_is_reached():
    """From the first phase (init's, or the one its stage leads to) every
    phase is reached, and PH_DONE."""
    code = engine_plan.SEQUENCER.read_text()
    rows = {ph: nexts for ph, _, nexts in engine_plan.plan(code)}
    returns = engine_plan.returns(engine_plan.plan_ways(code))
    first = engine_plan.enum_comments(engine_plan.PRIV.read_text(), "PH_")[0][0]
    reached = {first, "PH_GA_START"}
    todo = [first, "PH_GA_START"]
    while todo:
        for _, nxt in rows.get(todo.pop(), []):
            for to in (returns if nxt == engine_plan.RETURN else [nxt]):
                if to not in reached:
                    reached.add(to)
                    todo.append(to)
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
