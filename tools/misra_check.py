#!/usr/bin/env python3
"""MISRA C:2012 check of lib/ with cppcheck's MISRA addon, against the
deviations kept in tools/misra_deviations.txt (explained in docs/misra.md).

Every finding must be covered by a deviation:
  <rule> *      *      <reason>   the rule is not followed anywhere in lib/
  <rule> <file> <n>    <reason>   at most n findings of the rule in that file
The check fails on a finding no deviation covers, on a file with more
findings of a rule than its deviation allows, and on a deviation whose
reason still starts with REVIEW.

Usage: python3 tools/misra_check.py [--update] [--write-doc]
  --update     rewrite tools/misra_deviations.txt from the current findings:
               counts follow the code, reasons are kept, a new (rule, file)
               pair gets the reason "REVIEW: ..." for a person to replace
               (until then the check fails); pairs no longer found go.
  --write-doc  rewrite docs/reports/misra.md, the deviations by file (its
               prose in tools/misra_check.md.in)
cppcheck analyses the float and the double configuration; a finding of
either counts once per line.
"""
import argparse
import collections
import pathlib
import re
import shutil
import string
import subprocess
import sys

from pdtsupport import provenance

ROOT = pathlib.Path(__file__).resolve().parent.parent
DEVIATIONS = ROOT / "tools" / "misra_deviations.txt"
REPORT = ROOT / "docs" / "reports" / "misra.md"
TEMPLATE = pathlib.Path(__file__).with_name("misra_check.md.in")
REVIEW = "REVIEW: new finding; give the reason it is kept, or fix the code"


def run_cppcheck():
    if shutil.which("cppcheck") is None:
        sys.exit("cppcheck not found (apt-get install cppcheck)")
    sources = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "lib" / "src").glob("*.c"))
    findings = set()
    for real in ("0", "1"):
        build = ROOT / "build" / f"misra-{'double' if real == '1' else 'float'}"
        # A fresh analysis every time: cppcheck's cache, kept across changes
        # of the headers, reported their declarations a second time.
        shutil.rmtree(build, ignore_errors=True)
        build.mkdir(parents=True, exist_ok=True)
        res = subprocess.run(
            ["cppcheck", "--addon=misra", "--std=c99", "--language=c", "--platform=arm32-wchar_t2",
             f"-DPDT_REAL_DOUBLE={real}", "-UPDT_USER_CONFIG_FILE", "-Ilib/include", "-Ilib/src",
             "--enable=warning,portability", "--inline-suppr", "--quiet", "--error-exitcode=0",
             f"--cppcheck-build-dir={build}",
             "--template={file}|{line}|{id}|{severity}|{message}", *sources],
            cwd=ROOT, capture_output=True, text=True)
        if res.returncode != 0:
            sys.exit(f"cppcheck failed:\n{res.stderr}")
        for line in res.stderr.splitlines():
            parts = line.split("|", 4)
            if len(parts) != 5:
                continue
            path, lineno, ident, _sev, msg = parts
            path = str(pathlib.Path(path).resolve().relative_to(ROOT)) if path else "?"
            rule = ident[len("misra-c2012-"):] if ident.startswith("misra-c2012-") else ident
            findings.add((rule, path, int(lineno or 0), "" if ident.startswith("misra") else msg))
    return sorted(findings, key=lambda f: (rule_key(f[0]), f[1], f[2]))


def rule_key(rule):
    nums = re.findall(r"\d+", rule)
    return (0, [int(n) for n in nums]) if nums and rule[0].isdigit() else (1, [rule])


def read_deviations():
    devs = collections.OrderedDict()
    if not DEVIATIONS.exists():
        return devs
    for line in DEVIATIONS.read_text().splitlines():
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        rule, where, count, reason = (line.split(None, 3) + ["", ""])[:4]
        devs[(rule, where)] = (count, reason.strip())
    return devs


def check(findings, devs):
    by_pair = collections.defaultdict(list)
    for f in findings:
        by_pair[(f[0], f[1])].append(f)
    errors = []
    for (rule, path), items in sorted(by_pair.items(), key=lambda kv: (rule_key(kv[0][0]), kv[0][1])):
        if (rule, "*") in devs:
            continue
        dev = devs.get((rule, path))
        if dev is None:
            errors += [f"{p}:{ln}: {r} {msg}".rstrip() + " (no deviation)" for r, p, ln, msg in items]
        elif dev[0] != "*" and len(items) > int(dev[0]):
            errors.append(f"{path}: rule {rule}: {len(items)} findings, the deviation allows "
                          f"{dev[0]}; new at one of lines "
                          + ", ".join(str(i[2]) for i in items))
    for (rule, where), (_count, reason) in devs.items():
        if reason.startswith("REVIEW"):
            errors.append(f"deviation {rule} {where} still needs its reason (tools/misra_deviations.txt)")
    return errors


def update(findings, devs):
    counts = collections.Counter((f[0], f[1]) for f in findings)
    out = collections.OrderedDict()
    for key, (count, reason) in devs.items():
        if key[1] == "*":
            out[key] = (count, reason)
    for (rule, path), n in sorted(counts.items(), key=lambda kv: (rule_key(kv[0][0]), kv[0][1])):
        if (rule, "*") in out:
            continue
        old = devs.get((rule, path))
        out[(rule, path)] = (str(n), old[1] if old else REVIEW)
    header = [line for line in DEVIATIONS.read_text().splitlines() if line.startswith("#")] \
        if DEVIATIONS.exists() else []
    rows = header + [""]
    width = max(len(p) for _r, p in out) if out else 1
    for (rule, where), (count, reason) in sorted(out.items(),
                                                 key=lambda kv: (kv[0][1] != "*", rule_key(kv[0][0]),
                                                                 kv[0][1])):
        rows.append(f"{rule:<6} {where:<{width}} {count:>3} {reason}")
    DEVIATIONS.write_text("\n".join(rows) + "\n")


def write_doc(findings, devs):
    counts = collections.Counter((f[0], f[1]) for f in findings)
    per_rule = collections.defaultdict(list)
    for (rule, path), n in counts.items():
        per_rule[rule].append(f"{pathlib.Path(path).name} ({n})")
    lines = ["| rule | where (findings) | reason |", "|---|---|---|"]
    seen = set()
    for (rule, where), (_count, reason) in sorted(devs.items(),
                                                  key=lambda kv: (rule_key(kv[0][0]), kv[0][1])):
        if rule in seen:
            continue
        seen.add(rule)
        places = ", ".join(sorted(per_rule.get(rule, []))) or "none"
        reasons = sorted({r for (ru, _w), (_c, r) in devs.items() if ru == rule})
        lines.append(f"| {rule} | {places} | {' / '.join(reasons)} |")
    cppcheck = subprocess.run(["cppcheck", "--version"], capture_output=True,
                              text=True).stdout.strip()
    REPORT.write_text(string.Template(TEMPLATE.read_text()).substitute(
        cppcheck=cppcheck, findings=len(findings), table="\n".join(lines),
        **provenance.fields()))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--update", action="store_true")
    ap.add_argument("--write-doc", action="store_true")
    args = ap.parse_args()
    findings = run_cppcheck()
    devs = read_deviations()
    if args.update:
        update(findings, devs)
        devs = read_deviations()
        print(f"wrote {DEVIATIONS.relative_to(ROOT)}: review the diff")
    if args.write_doc:
        write_doc(findings, devs)
        print(f"wrote {REPORT.relative_to(ROOT)}")
    errors = check(findings, devs)
    rules = collections.Counter(f[0] for f in findings)
    print(f"MISRA C:2012 (cppcheck): {len(findings)} findings in {len(rules)} rules, "
          f"{len(errors)} not covered by tools/misra_deviations.txt")
    for e in errors:
        print("  " + e)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
