"""Test vectors of the real FFT (lib/src/pdt_fft.c) from numpy.fft.rfft.

For each size in SIZES the input is n pseudo-random integers q in
[-4096, 4095] from splitmix64 (draws below), and the signal is x = q / 4096: exactly
representable in float, so both C builds transform the same numbers numpy
does. The header stores

- ``fft_q_<n>``: the integers q (int16_t; the C test divides by
  FFT_VEC_DENOM, which is exact);
- ``fft_spec_<n>``: numpy.fft.rfft(x) in the library's packed layout
  (Re X0, Re X[n/2], then Re/Im of X1 .. X[n/2 - 1]), in double;
- ``fft_mag_<n>``: abs(numpy.fft.rfft(x)), n/2 + 1 values.

Storing the inputs as integers keeps the file small (about 0.4 MB for all
sizes, 8192 included), so the C test needs no copy of the generator.
"""
import numpy as np

from pdtsupport.rng import SplitMix64 as Rng

from . import _emit

SIZES = (16, 32, 64, 128, 256, 1024, 8192)
DENOM = 4096
FILE = "fft_vectors.h"


def draws(seed, count):
    """`count` integers in [-4096, 4095]: the 13 top bits of splitmix64
    (pdtsupport.rng), less 4096."""
    return Rng.keyed(seed).bits(13, count, DENOM)


def seed_for(n):
    """A different, fixed seed per size."""
    return 0x5EED0000 + n


def signal(n):
    """The integers q and the float64 signal q / DENOM for size n."""
    q = draws(seed_for(n), n)
    return q, np.asarray(q, dtype=np.float64) / DENOM


def pack(spectrum):
    """numpy's n/2 + 1 complex bins -> the library's n packed reals."""
    spectrum = np.asarray(spectrum)
    half = spectrum.size - 1
    out = np.empty(2 * half)
    out[0] = spectrum[0].real
    out[1] = spectrum[half].real
    out[2::2] = spectrum[1:half].real
    out[3::2] = spectrum[1:half].imag
    return out


def unpack(packed):
    """Inverse of pack(): n packed reals -> n/2 + 1 complex bins."""
    packed = np.asarray(packed, dtype=np.float64)
    half = packed.size // 2
    out = np.empty(half + 1, dtype=np.complex128)
    out[0] = packed[0]
    out[half] = packed[1]
    out[1:half] = packed[2::2] + 1j * packed[3::2]
    return out


def generate():
    body = ["#include <stdint.h>\n",
            "/* Inputs are fft_q_<n>[j] / FFT_VEC_DENOM (exact in float). */\n"
            f"#define FFT_VEC_DENOM {DENOM}\n"]
    for n in SIZES:
        q, x = signal(n)
        spectrum = np.fft.rfft(x)
        body.append(f"/* n = {n}, seed {seed_for(n):#x} */\n")
        body.append(_emit.int_array("int16_t", f"fft_q_{n}", q))
        body.append(_emit.array("double", f"fft_spec_{n}", pack(spectrum)))
        body.append(_emit.array("double", f"fft_mag_{n}", np.abs(spectrum)))
    return {FILE: _emit.header(FILE, "\n".join(body), "tools/vectorgen/fft.py (numpy.fft.rfft)")}
