"""tools/check_function_length.py: a long function fails, unless its file and
name are on the --allow list; an entry that is not needed is named; the
library and the tools pass with the project's allow-list."""
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tools" / "check_function_length.py"


def check(*args):
    return subprocess.run([sys.executable, str(SCRIPT), "--max", "3", *map(str, args)],
                          capture_output=True, text=True, cwd=ROOT)


def source(tmp_path):
    body = "    x++;\n" * 5
    (tmp_path / "a.c").write_text(f"static void longer(int x)\n{{\n{body}}}\n\n"
                                  "static void short_one(void)\n{\n    f();\n}\n")
    return tmp_path / "a.c"


def test_a_long_function_fails(tmp_path):
    r = check(source(tmp_path))
    assert r.returncode == 1
    assert "longer() has 5 lines (at most 3)" in r.stdout
    assert "short_one" not in r.stdout


def test_an_allowed_function_passes_and_an_idle_entry_is_named(tmp_path):
    f = source(tmp_path)
    allow = tmp_path / "allow.txt"
    allow.write_text(f"# a comment\n{f} longer  # being split\n{f} short_one\n")
    r = check("--allow", allow, f)
    assert r.returncode == 0, r.stdout
    assert "(allowed for now)" in r.stdout
    assert "short_one() is on the allow-list and not over 3 lines" in r.stdout


def test_the_library_and_the_tools_pass():
    r = subprocess.run([sys.executable, str(SCRIPT), "--max", "80", "--allow",
                        "tools/function_length_allow.txt", "lib", "tools"],
                       capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stdout
