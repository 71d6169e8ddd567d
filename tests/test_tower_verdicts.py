"""The frictionless tower's monodromy gives the verdict of its modes (multipliers on the unit circle)."""
import numpy as np
import pytest

import kapitza


@pytest.mark.parametrize("lengths", [[0.2], [0.2, 0.2], [0.3, 0.2, 0.1]])
def test_chain_floquet_without_friction_agrees_with_the_modes(lengths):
    ch = kapitza.Chain(lengths)
    rng = np.random.default_rng(len(lengths))
    seen = set()
    for f, s in zip(np.exp(rng.uniform(np.log(20.0), np.log(600.0), 40)), np.exp(rng.uniform(np.log(0.002), np.log(0.1), 40))):
        T, A = kapitza.SquareWave().from_rig(f, stroke=s)
        fl = kapitza.chain_floquet(ch, T=float(T), A=float(A))
        rep = kapitza.analyze_chain(ch, T=float(T), A=float(A))
        assert fl.stable == rep.stable
        if fl.stable:
            assert fl.growth == 0.0 and np.allclose(np.abs(fl.multipliers), 1.0, atol=1e-9)
        seen.add(fl.stable)
    assert seen == {True, False}
