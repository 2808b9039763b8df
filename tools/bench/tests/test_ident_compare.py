"""tools/bench/ident_compare.py's diff: the same answers pass, one changed
byte or exit code fails, and calls of one file only are not compared."""
import json
import subprocess
import sys

from pdtbench import ident_compare


def write(path, rows):
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))


def diff(tmp_path, a, b):
    write(tmp_path / "a.jsonl", a)
    write(tmp_path / "b.jsonl", b)
    return subprocess.run([sys.executable, ident_compare.__file__, "diff",
                           str(tmp_path / "a.jsonl"), str(tmp_path / "b.jsonl")],
                          capture_output=True, text=True)


def row(key, rc=0, out='{"K": 2.0}\n', err=""):
    return {"key": key, "rc": rc, "out": out, "err": err}


def test_same_answers_pass(tmp_path):
    r = diff(tmp_path, [row("a"), row("b")], [row("a"), row("b")])
    assert r.returncode == 0, r.stdout
    assert "2 calls in both files, 0 differ" in r.stdout


def test_a_changed_answer_fails(tmp_path):
    r = diff(tmp_path, [row("a"), row("b")], [row("a"), row("b", out='{"K": 2.0000001}\n')])
    assert r.returncode == 1
    assert "differs: b" in r.stdout
    assert diff(tmp_path, [row("a")], [row("a", rc=3)]).returncode == 1


def test_a_run_cut_short_compares_the_calls_of_both(tmp_path):
    r = diff(tmp_path, [row("a"), row("b")], [row("a")])
    assert r.returncode == 0
    assert "1 only in A" in r.stdout
    assert diff(tmp_path, [row("a")], [row("b")]).returncode == 1
