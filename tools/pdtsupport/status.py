"""pdt_status_t read from lib/include/pdt/pdt_status.h, so that no status
code is typed in Python: STATUS {name: value} and NAMES {value: name}, the
names without PDT_ / PDT_ERR_ ("OK", "NO_EXCITATION", ...).

The header parser is the Python package's (python/pdtfit/_cheader.py),
loaded from its file so that the tools need neither the compiled package
nor a second parser.
"""
import importlib.util
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[2]
HEADER = ROOT / "lib" / "include" / "pdt" / "pdt_status.h"


def _load_parser():
    spec = importlib.util.spec_from_file_location(
        "_pdt_cheader", ROOT / "python" / "pdtfit" / "_cheader.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


cheader = _load_parser()
NAMES = cheader.status_names(HEADER)
STATUS = {name: value for value, name in NAMES.items()}
