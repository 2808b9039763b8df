"""pdtsupport.template.parts: a report's template file in parts, and the
parts the benchmark scripts read from theirs."""
import pathlib
import string

from pdtsupport import template

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_a_part_runs_to_the_next_marker_less_one_newline(tmp_path):
    f = tmp_path / "t.md.in"
    f.write_text("@@ one\n# Head\n\nText ${x}.\n\n@@ two\n (inline)\n@@ three\nlast\n")
    parts = template.parts(f)
    assert set(parts) == {"one", "two", "three"}
    assert all(isinstance(p, string.Template) for p in parts.values())
    assert parts["one"].substitute(x=1) == "# Head\n\nText 1.\n"
    assert parts["two"].substitute() == " (inline)"
    assert parts["three"].substitute() == "last"


def test_the_benchmarks_templates_have_their_parts():
    bench = ROOT / "tools" / "bench"
    assert set(template.parts(bench / "run_ident_bench_parts.md.in")) == {
        "results", "update_speed_note", "certainty", "certainty_missing"}
    assert set(template.parts(bench / "certainty_run.md.in")) == {
        "run", "reference_note", "in_parts", "part", "part_cases", "interrupted", "elapsed",
        "resumed", "summary", "examples"}
