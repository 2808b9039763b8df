"""The status codes as the Python side reads them from pdt_status.h: every
code the library declares, with the conventions the C API promises (OK 0,
errors negative, RUNNING positive), and the names the reference uses."""
from pdtref import excite, tune
from pdtsupport.status import HEADER


def test_every_declared_status_is_read(pdt_status):
    declared = [line.split("=")[0].strip() for line in HEADER.read_text().splitlines()
                if line.strip().startswith("PDT_") and "=" in line]
    assert len(pdt_status) == len(declared) and len(set(pdt_status.values())) == len(declared)
    assert pdt_status["OK"] == 0 and pdt_status["RUNNING"] > 0
    errors = {n: v for n, v in pdt_status.items() if n not in ("OK", "RUNNING")}
    assert errors and all(v < 0 for v in errors.values())


def test_reference_uses_the_header_codes(pdt_status):
    assert tune.UNSTABLE == pdt_status["UNSTABLE"] and tune.POOR_FIT == pdt_status["POOR_FIT"]
    assert tune.MS_LIMIT == pdt_status["MS_LIMIT"]
    assert excite.ERR_SETPOINT == pdt_status["SETPOINT"] and excite.RUNNING == pdt_status["RUNNING"]
