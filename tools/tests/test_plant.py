"""pdtsupport.plant, the tools' plant simulator, against closed forms and
against itself by its other ways (lsim, the fractional form, the
first-order recursion)."""
import math

import numpy as np
import pytest

from pdtsupport import plant


def fine_samples(num, den, L, Ts, sub, u):
    """y(k Ts) for the held input u, stepped on the fine grid Ts / sub."""
    p = plant.Fine(num, den, Ts / sub, int(round(L / (Ts / sub))))
    y = np.empty(len(u))
    w = 0.0
    for k, uk in enumerate(np.repeat(u, sub)):
        if k % sub == 0:
            y[k // sub] = p.output_fed(w)
        w = p.advance(uk)
    return y


def test_step_response_of_a_fopdt_is_the_closed_form():
    h, L = 0.01, 0.3
    y = plant.step_response([2.0], [5.0, 1.0], L, h, 400)
    t = np.arange(400) * h
    want = np.where(t > L, 2.0 * -np.expm1(-(t - L) / 5.0), 0.0)
    assert np.max(np.abs(y - want)) < 1e-13


@pytest.mark.parametrize("num,den,L", [
    ([2.0], [5.0, 1.0], 1.3),
    ([1.5], list(np.polymul([4.0, 1.0], [1.5, 1.0])), 0.8),
    ([-0.5, 1.0], list(np.polymul([2.0, 1.0], [1.0, 1.0])), 0.0),
    ([0.05], [0.5, 1.0, 0.0], 1.0),
])
def test_fine_steps_and_lsim_agree(num, den, L):
    u = np.where(np.arange(300) % 40 < 20, 1.0, -0.5)
    u[:5] = 0.0
    a = plant.simulate(num, den, L, u, 0.1)
    b = fine_samples(num, den, L, 0.1, 20, u)
    assert np.max(np.abs(a - b)) < 1e-12 * max(1.0, np.max(np.abs(a)))


@pytest.mark.parametrize("L", [0.0, 0.25, 0.3, 1.05])
def test_fractional_form_samples_the_fine_one(L):
    """The scan-period form with the dead time (l + f) Ts gives the fine
    grid's samples when f Ts is a whole number of its steps."""
    num, den, Ts = [1.2], list(np.polymul([3.0, 1.0], [0.7, 1.0])), 0.1
    Phi, G0, G1, C, l = plant.fractional(num, den, L, Ts)
    u = np.sin(0.05 * np.arange(200)) + (np.arange(200) > 30)
    x = np.zeros(len(C))
    y = np.empty(len(u))
    past = [0.0] * (l + 2)  # u(k - j), j = 0 .. l + 1
    for k, uk in enumerate(u):
        y[k] = C @ x
        past = [uk] + past[:-1]
        x = Phi @ x + G0 * past[l] + G1 * past[l + 1]
    assert np.max(np.abs(y - fine_samples(num, den, L, Ts, 20, u))) < 1e-12


def test_first_order_is_the_fine_fopdt():
    K, tau, Ts, l = -1.7, 6.0, 0.5, 3
    u = np.where(np.arange(150) % 24 < 12, 1.0, -1.0)
    y = plant.first_order(K, math.exp(-Ts / tau), u, l)
    assert np.max(np.abs(y - fine_samples([K], [tau, 1.0], l * Ts, Ts, 1, u))) < 1e-12

