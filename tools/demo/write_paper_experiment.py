#!/usr/bin/env python3
"""Runs the demo (float build) and writes docs/reports/paper-experiment.md: its
output verbatim, with the explanation of how it compares with the paper (the
prose is the template paper_experiment.md.in beside this file).

Usage: python3 tools/demo/write_paper_experiment.py
"""
import argparse
import pathlib
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]

TEMPLATE = pathlib.Path(__file__).with_name("paper_experiment.md.in")


def main():
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(ROOT / "build" / "release"), "-G", "Ninja",
                    "-DCMAKE_BUILD_TYPE=Release", "-DPDT_BUILD_TESTS=OFF"], check=True,
                   stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(ROOT / "build" / "release"), "--target", "pdt_demo"],
                   check=True, stdout=subprocess.DEVNULL)
    out = subprocess.run([str(ROOT / "build" / "release" / "tools" / "pdt_demo")], check=True,
                         capture_output=True, text=True).stdout
    (ROOT / "docs" / "reports" / "paper-experiment.md").write_text(TEMPLATE.read_text().format(output=out))
    print("wrote docs/reports/paper-experiment.md")


if __name__ == "__main__":
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    main()
