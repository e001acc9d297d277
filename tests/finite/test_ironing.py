"""Ironing (issue [5/6], after Yang, Laursen and Meng 2005): the die's force over the slide.

A stiff half-ring die meshed twice as coarse as the neo-Hookean block it irons, the
multiplier on the die's arc: node-to-segment's force jumps as the block's nodes pass the
die's nodes, segment-to-segment's integral over the sub-segments of both surfaces does
not (the issue: "the S2S curve is smooth, node-to-segment is not").
"""

from mpi4py import MPI

import numpy as np
import pytest

from paper.large_sliding import IRONING, ironing, oscillation

comm = MPI.COMM_WORLD


def test_oscillation_measures_a_ripple_on_a_trend():
    """A quartic trend has none; a sine ripple of amplitude a has 2a over the mean."""
    s = np.linspace(0.0, 4.0, 401)
    trend = -2.0 - 0.3 * (s - 2.0) ** 2 + 0.05 * (s - 2.0) ** 4
    record = {"s": s, "d": np.full_like(s, IRONING["press"]), "fy": trend, "fx": 0 * s}
    assert oscillation(record) < 1e-12
    window = (s >= 1.0) & (s <= 3.0)
    mean = np.mean(np.abs(trend[window]))
    # A ripple of period 0.2 (a few elements) over the window of length 2: the quartic
    # takes out little of it, but bends at the window's ends, where the sine's projection
    # on it is largest (order (4 + 1)^2 / (2 pi 10 periods)): 2a within 15%.
    ripple = 1e-3 * np.sin(2 * np.pi * s / 0.2 + 0.3)
    measured = oscillation({**record, "fy": trend + ripple})
    assert measured == pytest.approx(2e-3 / mean, rel=0.15)
    # Raw: the trend's own range over the window, in closed form (its extremes on
    # [1, 3] at s = 2 and at the window's ends: -2 and -2.3 + 0.05).
    assert oscillation(record, raw=True) == pytest.approx(0.25 / mean, rel=1e-12)
    # Too few steps in the window to tell a ripple from a trend.
    assert np.isnan(oscillation({k: v[::60] for k, v in record.items()}))


def test_ironing_coarse_die_segment_to_segment_smooth():
    """h = 0.6, die 1.2, 80 slide steps: the mortar force's oscillation <= 1/3 of NTS's."""
    runs = {
        method: ironing(comm, 0.6, method, slide_steps=80, contactor="die", die_h=1.2)
        for method in ("segment-to-segment", "node-to-segment")
    }
    mortar, nts = (runs[m]["oscillation"] for m in ("segment-to-segment", "node-to-segment"))
    assert mortar <= nts / 3
    for run in runs.values():
        # Pressed, then slid: the die pushes the block down (the force on the die is up
        # from the block, down from its held ends), every step converged.
        pressed = np.asarray(run["d"]) == IRONING["press"]
        assert np.all(np.asarray(run["fy"])[pressed] < 0)
        assert run["probe"]["settled"] and run["probe"]["order"] > 1.8
