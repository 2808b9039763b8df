#!/usr/bin/env python3
"""Checks pdtfit's package manifests as far as this machine allows.

- PlatformIO library.json: required keys, the version of pdt_common.h, the
  source, include and exported paths exist.
- ESP-IDF idf_component.yml: keys, version, every file pattern matches, the
  ESP_PLATFORM branch of CMakeLists.txt registers the component.
- Zephyr zephyr/module.yml and zephyr/Kconfig: the paths exist, and every
  Kconfig option mirrors the pdt_config.h setting of the same name (default
  and range).
- Arduino: generates the library (tools/make_arduino_library.py), checks
  library.properties, and compiles the example sketch the way the Arduino
  builder does (library sources as C, the sketch as C++ with Arduino.h
  first) with arm-none-eabi-gcc/g++ for a Cortex-M4F and a Cortex-M0+, and
  links it.

    python3 tools/check_packages.py [--no-compile]
"""
import argparse
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent
errors = []


def fail(msg):
    errors.append(msg)
    print("FAIL:", msg)


def version():
    text = (ROOT / "lib/include/pdt/pdt_common.h").read_text()
    return ".".join(re.search(r"#define PDT_VERSION_%s (\d+)" % p, text).group(1)
                    for p in ("MAJOR", "MINOR", "PATCH"))


def check_platformio(ver):
    m = json.loads((ROOT / "library.json").read_text())
    for key in ("name", "version", "description", "license", "frameworks", "platforms", "build"):
        if key not in m:
            fail("library.json: no %r" % key)
    if m.get("version") != ver:
        fail("library.json: version %s, pdt_common.h %s" % (m.get("version"), ver))
    b = m.get("build", {})
    for key in ("srcDir", "includeDir"):
        if not (ROOT / b.get(key, "?")).is_dir():
            fail("library.json: build.%s %r is not a folder" % (key, b.get(key)))
    for flag in b.get("flags", []):
        # The real type and the limits are the project's to choose
        # (build_flags); a flag here would fight them.
        if re.match(r"-D\s*PDT_", flag):
            fail("library.json: flag %r overrides a pdt_config.h setting" % flag)
        if flag.startswith("-I"):
            if not (ROOT / flag[2:].strip()).is_dir():
                fail("library.json: include flag %r names no folder" % flag)
    for h in m.get("headers", []):
        if not (ROOT / b.get("includeDir", "") / h).is_file():
            fail("library.json: header %r not in includeDir" % h)
    for p in m.get("export", {}).get("include", []):
        if not (ROOT / p).exists():
            fail("library.json: exported %r does not exist" % p)
    print("library.json: ok")


def check_idf(ver):
    m = yaml.safe_load((ROOT / "idf_component.yml").read_text())
    if str(m.get("version")) != ver:
        fail("idf_component.yml: version %s, pdt_common.h %s" % (m.get("version"), ver))
    for key in ("description", "license", "dependencies"):
        if key not in m:
            fail("idf_component.yml: no %r" % key)
    for pat in m.get("files", {}).get("include", []):
        if not list(ROOT.glob(pat)):
            fail("idf_component.yml: %r matches no file" % pat)
    cm = (ROOT / "CMakeLists.txt").read_text()
    branch = re.search(r"if\(ESP_PLATFORM\)(.*?)return\(\)", cm, re.S)
    if not branch or "idf_component_register" not in branch.group(1):
        fail("CMakeLists.txt: no ESP_PLATFORM branch registering the component")
    elif cm.index("if(ESP_PLATFORM)") > cm.index("project("):
        fail("CMakeLists.txt: the ESP_PLATFORM branch must come before project()")
    if "Kconfig" not in m.get("files", {}).get("include", []):
        fail("idf_component.yml: the component's Kconfig is not included")
    if branch:
        check_kconfig(ROOT / "Kconfig", "Kconfig", branch.group(1), "the ESP_PLATFORM branch")
    print("idf_component.yml: ok")


def config_settings():
    """{name: (default, lo, hi)} of pdt_config.h's integer settings; for a
    default that follows SIZE_MAX, the one of a 32-bit size_t (Zephyr's)."""
    text = (ROOT / "lib/include/pdt/pdt_config.h").read_text()
    out = {}
    for name, val in re.findall(
            r"#ifndef (PDT_\w+)\n(?:#if !defined\(SIZE_MAX\) \|\| \(SIZE_MAX > 0xFFFFu\)\n)?"
            r"#define \1 (\d+)u?\n", text):
        rng = re.search(r"#if \(?%s < (\d+)\)?(?: \|\| \(%s > (\d+)\))?" % (name, name), text)
        lo = int(rng.group(1)) if rng else None
        hi = int(rng.group(2)) if rng and rng.group(2) else None
        out[name] = (int(val), lo, hi)
    return out


def check_kconfig(path, name, cmake, cmake_name):
    """Every option of the Kconfig at path mirrors a pdt_config.h setting
    (default and range), every setting has one, and cmake uses each."""
    text = path.read_text() if path.is_file() else ""
    if not text:
        fail("%s: missing" % name)
        return
    settings = config_settings()
    opts = re.findall(r"^config (PDTFIT_\w+)\n(.*?)(?=^config |^endif|^endmenu|\Z)", text,
                      re.S | re.M)
    seen = set()
    for opt, body in opts:
        if opt == "PDTFIT":
            continue
        c_name = "PDT_" + opt[len("PDTFIT_"):]
        seen.add(c_name)
        if c_name not in settings:
            fail("%s: %s mirrors no pdt_config.h setting" % (name, opt))
            continue
        if "\tbool" in body:
            continue
        default, lo, hi = settings[c_name]
        d = re.search(r"default (\d+)", body)
        r = re.search(r"range (\d+) (\d+)", body)
        if not d or int(d.group(1)) != default:
            fail("%s: %s default differs from pdt_config.h (%d)" % (name, opt, default))
        if lo is not None and (not r or int(r.group(1)) != lo or
                               (hi is not None and int(r.group(2)) != hi)):
            fail("%s: %s range differs from pdt_config.h" % (name, opt))
    for c_name in settings:
        if c_name not in seen:
            fail("%s: no option for %s" % (name, c_name))
    for opt, _ in opts:
        if opt != "PDTFIT" and "CONFIG_" + opt not in cmake:
            fail("%s: CONFIG_%s is not used" % (cmake_name, opt))


def check_zephyr():
    m = yaml.safe_load((ROOT / "zephyr/module.yml").read_text())
    build = m.get("build", {})
    if not (ROOT / build.get("cmake", "?") / "CMakeLists.txt").is_file():
        fail("zephyr/module.yml: build.cmake has no CMakeLists.txt")
    kconfig = ROOT / build.get("kconfig", "?")
    if not kconfig.is_file():
        fail("zephyr/module.yml: build.kconfig is not a file")
        return
    check_kconfig(kconfig, "zephyr/Kconfig", (ROOT / "zephyr/CMakeLists.txt").read_text(),
                  "zephyr/CMakeLists.txt")
    print("zephyr module: ok")


CPUS = {
    "cortex-m4f": ["-mcpu=cortex-m4", "-mthumb", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard"],
    "cortex-m0plus": ["-mcpu=cortex-m0plus", "-mthumb", "-mfloat-abi=soft"],
}


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        fail("%s\n%s%s" % (" ".join(map(str, cmd)), r.stdout, r.stderr))
        return False
    return True


def check_arduino(ver, compile_it):
    out = ROOT / "build" / "arduino"
    gen = subprocess.run([sys.executable, str(ROOT / "tools/make_arduino_library.py"), str(out)],
                         capture_output=True, text=True, check=True)
    lib = Path(gen.stdout.strip())
    props = dict(line.split("=", 1) for line in (lib / "library.properties").read_text().splitlines()
                 if "=" in line)
    for key in ("name", "version", "author", "maintainer", "sentence", "paragraph", "category",
                "architectures", "includes"):
        if key not in props:
            fail("library.properties: no %r" % key)
    if props.get("version") != ver:
        fail("library.properties: version %s, pdt_common.h %s" % (props.get("version"), ver))
    for inc in props.get("includes", "").split(","):
        if not (lib / "src" / inc.strip()).is_file():
            fail("library.properties: includes %r is not in src/" % inc)
    sketches = sorted(lib.glob("examples/*/*.ino"))
    if not sketches:
        fail("arduino: no example sketch")
    for s in sketches:
        if s.stem != s.parent.name:
            fail("arduino: sketch %s is not in a folder of its name" % s)
    print("library.properties: ok")
    if not compile_it:
        return
    if not shutil.which("arm-none-eabi-g++"):
        fail("arm-none-eabi-g++ not found (apt-get install gcc-arm-none-eabi)")
        return
    core = ROOT / "packaging/arduino/ci-core"
    for cpu, flags in CPUS.items():
        obj = out / ("obj-" + cpu)
        obj.mkdir(parents=True, exist_ok=True)
        objs = []
        for c in sorted((lib / "src").glob("*.c")):
            o = obj / (c.stem + ".o")
            if not run(["arm-none-eabi-gcc", *flags, "-Os", "-std=gnu11", "-Wall", "-Werror",
                        "-ffunction-sections", "-fdata-sections", "-I", str(lib / "src"),
                        "-c", str(c), "-o", str(o)]):
                return
            objs.append(o)
        lib_objs = objs
        for s in sketches:
            objs = list(lib_objs)
            cpp = obj / (s.name + ".cpp")
            cpp.write_text('#include <Arduino.h>\n#line 1 "%s"\n%s' % (s.name, s.read_text()))
            sources = [cpp, core / "main.cpp"]
            for src in sources:
                o = obj / (Path(src).name + ".o")
                if not run(["arm-none-eabi-g++", *flags, "-Os", "-std=gnu++11", "-fno-exceptions",
                            "-fno-rtti", "-Wall", "-Werror", "-I", str(lib / "src"), "-I", str(core),
                            "-c", str(src), "-o", str(o)]):
                    return
                objs.append(o)
            elf = obj / (s.stem + ".elf")
            if not run(["arm-none-eabi-g++", *flags, "-Wl,--gc-sections", "--specs=nano.specs",
                        "--specs=nosys.specs", *map(str, objs), "-lm", "-o", str(elf)]):
                return
            print("arduino: %s compiled and linked for %s" % (s.stem, cpu))
    check_arduino_avr(lib, sketches, out)


# The AVR example of each sketch folder: AutotuneMega must build and run on
# an ATmega2560 (simavr) and print gains; the others must refuse AVR with
# their #error.
AVR_SKETCH = "AutotuneMega"
AVR_FLAGS = ["-mmcu=atmega2560", "-DF_CPU=16000000UL", "-Os", "-ffunction-sections",
             "-fdata-sections"]


def avr_objects(lib, obj):
    objs = []
    for c in sorted((lib / "src").glob("*.c")):
        o = obj / (c.stem + ".o")
        if not run(["avr-gcc", *AVR_FLAGS, "-std=gnu11", "-Wall", "-Werror", "-I", str(lib / "src"),
                     "-c", str(c), "-o", str(o)]):
            return None
        objs.append(o)
    return objs


def check_arduino_avr(lib, sketches, out):
    if not (shutil.which("avr-g++") and shutil.which("simavr")):
        fail("avr-g++ or simavr not found (apt-get install gcc-avr avr-libc simavr)")
        return
    core = ROOT / "packaging/arduino/ci-core"
    obj = out / "obj-atmega2560"
    obj.mkdir(parents=True, exist_ok=True)
    objs = avr_objects(lib, obj)
    if objs is None:
        return
    for s in sketches:
        cpp = obj / (s.name + ".cpp")
        cpp.write_text('#include <Arduino.h>\n#line 1 "%s"\n%s' % (s.name, s.read_text()))
        cxx = ["avr-g++", *AVR_FLAGS, "-std=gnu++11", "-fno-exceptions", "-Wall", "-Werror",
               "-I", str(lib / "src"), "-I", str(core), "-c"]
        r = subprocess.run([*cxx, str(cpp), "-o", str(obj / (s.stem + ".o"))],
                           capture_output=True, text=True)
        if s.stem != AVR_SKETCH:
            if r.returncode == 0 or "#error" not in r.stderr:
                fail("arduino: %s does not refuse AVR with an #error" % s.stem)
            continue
        elf = obj / (s.stem + ".elf")
        if r.returncode != 0 or not run([*cxx, str(core / "main.cpp"), "-o", str(obj / "main.o")]) \
                or not run(["avr-g++", *AVR_FLAGS, "-Wl,--gc-sections", str(obj / (s.stem + ".o")),
                            str(obj / "main.o"), *map(str, objs), "-lm", "-o", str(elf)]):
            fail("arduino: %s does not build for the ATmega2560\n%s" % (s.stem, r.stderr))
            continue
        sim = subprocess.run(["simavr", "-m", "atmega2560", "-f", "16000000", str(elf)],
                             capture_output=True, text=True, timeout=600)
        if "Kc = " not in sim.stdout + sim.stderr:
            fail("arduino: %s printed no gains under simavr\n%s" % (s.stem, sim.stdout[-500:]))
            continue
        print("arduino: %s built for the ATmega2560 and printed its gains under simavr" % s.stem)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--no-compile", action="store_true",
                    help="check the Arduino library without compiling its example")
    args = ap.parse_args()
    ver = version()
    check_platformio(ver)
    check_idf(ver)
    check_zephyr()
    check_arduino(ver, not args.no_compile)
    if errors:
        print("%d package check(s) failed" % len(errors))
        return 1
    print("package manifests: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
