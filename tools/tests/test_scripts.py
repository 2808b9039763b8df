"""Every script of tools/ answers --help with its usage, exit status 0, and
does nothing else: no file written where it runs, nothing changed in the
checkout. Also the build's configuration without CMocka."""
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def scripts():
    """The programs of tools/: Python files with a main guard, shell files."""
    out = []
    for p in sorted((ROOT / "tools").rglob("*")):
        if "tests" in p.relative_to(ROOT).parts or not p.is_file():
            continue
        if p.suffix == ".sh" or (p.suffix == ".py" and
                                 'if __name__ == "__main__"' in p.read_text()):
            out.append(p)
    return out


def test_the_scripts_are_found():
    names = {p.name for p in scripts()}
    assert {"make_arduino_library.py", "check_docs.py", "test.sh", "certainty.py"} <= names


@pytest.mark.parametrize("script", scripts(), ids=lambda p: str(p.relative_to(ROOT)))
def test_script_help(script, tmp_path):
    cmd = ["bash", str(script)] if script.suffix == ".sh" else [sys.executable, str(script)]
    before = subprocess.run(["git", "status", "--porcelain"], cwd=ROOT, capture_output=True,
                            text=True).stdout
    r = subprocess.run(cmd + ["--help"], cwd=tmp_path, capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    assert len(r.stdout.strip().splitlines()) >= 2
    assert list(tmp_path.iterdir()) == []
    after = subprocess.run(["git", "status", "--porcelain"], cwd=ROOT, capture_output=True,
                           text=True).stdout
    assert after == before


def configure(tmp_path, *flags):
    """cmake's configure of the checkout with CMocka hidden: its result."""
    gen = ["-G", "Ninja"] if shutil.which("ninja") else []
    return subprocess.run(["cmake", "-S", str(ROOT), "-B", str(tmp_path / "b"), *gen,
                           "-DCMOCKA_INCLUDE_DIR=", *flags], capture_output=True, text=True,
                          timeout=300, env=dict(os.environ, CMAKE_BUILD_PARALLEL_LEVEL="1"))


@pytest.mark.skipif(shutil.which("cmake") is None, reason="no cmake")
def test_configure_without_cmocka_skips_the_tests(tmp_path):
    r = configure(tmp_path)
    assert r.returncode == 0, r.stderr
    assert "CMocka not found: the unit tests are skipped" in " ".join(r.stderr.split())


@pytest.mark.skipif(shutil.which("cmake") is None, reason="no cmake")
def test_configure_without_cmocka_refuses_asked_tests(tmp_path):
    r = configure(tmp_path, "-DPDT_BUILD_TESTS=ON")
    assert r.returncode != 0
    assert "CMocka not found: install libcmocka-dev" in " ".join(r.stderr.split())
