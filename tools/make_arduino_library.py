#!/usr/bin/env python3
"""Writes pdtfit as an Arduino library (Arduino's 1.5 library layout).

    python3 tools/make_arduino_library.py OUT_DIR

OUT_DIR/pdtfit/ then holds library.properties, src/ (the library's sources
and private headers, the public headers under src/pdt/, and pdtfit.h),
examples/ and LICENSE: zip it for the Library Manager's "Add .ZIP Library",
or copy it into the sketchbook's libraries/ folder. The tree itself cannot
be used as is, because the builder compiles src/ recursively with only
src/ on the include path.
"""
import argparse
import re
import shutil
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PKG = ROOT / "packaging" / "arduino"

# The Arduino architectures library.properties declares: only those whose
# CPU a target test runs on (tools/test.sh), each with the test. Add a row
# when a core gets one.
ARCHITECTURES = {
    "avr": "ATmega2560 under simavr (tests/target/avr); parts with less than 8 KiB of RAM "
           "run the PID only (the examples say so with #error)",
    "mbed_nano": "Cortex-M4F (Nano 33 BLE) under QEMU (tests/target)",
    "renesas_uno": "Cortex-M4F (UNO R4) under QEMU (tests/target)",
}


def version():
    text = (ROOT / "lib/include/pdt/pdt_common.h").read_text()
    parts = [re.search(r"#define PDT_VERSION_%s (\d+)" % p, text).group(1)
             for p in ("MAJOR", "MINOR", "PATCH")]
    return ".".join(parts)


def make(out_dir):
    lib = Path(out_dir) / "pdtfit"
    if lib.exists():
        shutil.rmtree(lib)
    src = lib / "src"
    (src / "pdt").mkdir(parents=True)
    for f in sorted((ROOT / "lib/src").iterdir()):
        if f.suffix in (".c", ".h"):
            shutil.copy2(f, src / f.name)
    for f in sorted((ROOT / "lib/include/pdt").rglob("*.h")):
        dest = src / "pdt" / f.relative_to(ROOT / "lib/include/pdt")
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(f, dest)
    shutil.copy2(PKG / "pdtfit.h", src / "pdtfit.h")
    shutil.copytree(PKG / "examples", lib / "examples")
    shutil.copy2(ROOT / "LICENSE", lib / "LICENSE")
    props = (PKG / "library.properties.in").read_text().replace("@VERSION@", version())
    props = props.replace("@ARCHITECTURES@", ",".join(ARCHITECTURES))
    (lib / "library.properties").write_text(props)
    return lib


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out_dir", metavar="OUT_DIR",
                    help="the folder to write pdtfit/ into (created when missing)")
    print(make(ap.parse_args().out_dir))
