"""Checks of the FFT test vectors (tools/vectorgen/fft.py).

The committed header is parsed back and compared with numpy.fft.rfft of the
parsed input, with scipy.fft.rfft and with a direct DFT sum, so a wrong
packing or a drifting generator shows up here before the C tests run.
"""
import pathlib
import re

import numpy as np
import pytest

TOOLS = pathlib.Path(__file__).resolve().parents[1]
ROOT = TOOLS.parent

from vectorgen import fft

HEADER = ROOT / "tests" / "vectors" / fft.FILE


def parse_arrays(text):
    """name -> list of numbers for every `static const T name[N] = {...};`."""
    arrays = {}
    pattern = re.compile(r"static const (\w+) (\w+)\[(\d+)\] = \{(.*?)\};", re.S)
    for ctype, name, count, body in pattern.findall(text):
        items = [s for s in (t.strip() for t in body.split(",")) if s]
        conv = int if ctype.startswith("int") else float
        values = [conv(s) for s in items]
        assert len(values) == int(count), name
        arrays[name] = values
    return arrays


@pytest.fixture(scope="module")
def committed():
    return parse_arrays(HEADER.read_text())


def test_draws_stream_is_stable():
    # Fixed values: a change here changes every committed vector.
    assert fft.draws(1, 6) == [-959, -3279, -3890, 3493, -1660, 3989]
    assert fft.draws(fft.seed_for(16), 4) == [1179, -659, 1163, 559]
    q = fft.draws(12345, 20000)
    assert min(q) >= -4096 and max(q) <= 4095
    # Roughly uniform: mean near zero, both ends reached.
    assert abs(np.mean(q)) < 60
    assert min(q) < -4000 and max(q) > 4000


def test_generation_matches_committed_file():
    files = fft.generate()
    assert list(files) == [fft.FILE]
    assert files[fft.FILE] == HEADER.read_text()
    assert len(files[fft.FILE].encode()) < 1_000_000


@pytest.mark.parametrize("n", fft.SIZES)
def test_vectors_agree_with_numpy(committed, n):
    q = committed[f"fft_q_{n}"]
    spec = np.array(committed[f"fft_spec_{n}"])
    mag = np.array(committed[f"fft_mag_{n}"])
    assert q == fft.draws(fft.seed_for(n), n)
    x = np.array(q, dtype=np.float64) / fft.DENOM
    # Exactly representable in float32.
    assert np.array_equal(x.astype(np.float32).astype(np.float64), x)

    ref = np.fft.rfft(x)
    assert spec.shape == (n,) and mag.shape == (n // 2 + 1,)
    # The text form round-trips doubles exactly.
    assert np.array_equal(spec, fft.pack(ref))
    assert np.array_equal(mag, np.abs(ref))


@pytest.mark.parametrize("n", [16, 32, 64, 128, 256])
def test_packing_against_direct_dft(committed, n):
    # X[k] = sum_j x[j] e^{-2 pi i j k / n}, summed directly with exact
    # integer phase indices, then packed by hand into the documented layout.
    x = np.array(committed[f"fft_q_{n}"], dtype=np.float64) / fft.DENOM
    j = np.arange(n)
    packed = np.empty(n)
    for k in range(n // 2 + 1):
        phase = 2.0 * np.pi * ((j * k) % n) / n
        re = float(np.sum(x * np.cos(phase)))
        im = float(-np.sum(x * np.sin(phase)))
        if k == 0:
            packed[0] = re
        elif k == n // 2:
            packed[1] = re
        else:
            packed[2 * k] = re
            packed[2 * k + 1] = im
    spec = np.array(committed[f"fft_spec_{n}"])
    assert np.allclose(spec, packed, rtol=0, atol=1e-12 * np.max(np.abs(packed)))


def test_pack_unpack_round_trip():
    x = np.array(fft.draws(7, 64), dtype=np.float64) / fft.DENOM
    spectrum = np.fft.rfft(x)
    assert np.array_equal(fft.unpack(fft.pack(spectrum)), spectrum)
    assert np.allclose(np.fft.irfft(fft.unpack(fft.pack(spectrum)), 64), x, atol=1e-15)
