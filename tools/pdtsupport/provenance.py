"""What a generated report names about its run: the commit of the tree and
the machine it ran on (docs/reports/)."""
import pathlib
import platform
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]


def commit():
    """The short hash of the checkout's HEAD, or "unknown" outside git."""
    run = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                         capture_output=True, text=True)
    return run.stdout.strip() or "unknown"


def machine():
    """The host's CPU model (or architecture), system and its release."""
    cpu = platform.machine()
    info = pathlib.Path("/proc/cpuinfo")
    if info.exists():
        names = [ln.split(":", 1)[1].strip() for ln in info.read_text().splitlines()
                 if ln.startswith("model name")]
        cpu = names[0] if names else cpu
    return f"{cpu}, {platform.system()} {platform.release()}"


def fields():
    """{"commit": ..., "machine": ...} for a template."""
    return {"commit": commit(), "machine": machine()}
