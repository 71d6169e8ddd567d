"""``search_bits``: the pair of adjacent doubles where a predicate changes, found with a fast
predicate that may err near the change and settled with a certified one. The certified change is
found wherever the fast one is off by up to 2^20 ulp, guided or not, and the bracket's own ends
carry no claim."""
import numpy as np
import pytest

from kapitza.drives._api import search_bits


def _problem(roots, err_ulp):
    """Rows with certified changes at ``roots`` (the first double of each that is True) and a fast
    predicate whose change is moved by ``err_ulp`` ulp; ``f`` a smooth function of the right sign."""
    roots = np.asarray(roots, float)
    shifted = (roots.view(np.int64) + np.asarray(err_ulp, np.int64)).view(np.float64)
    calls = {"fast": 0, "certified": 0}

    def make(where, key):
        def pred(x, rows):
            calls[key] += 1
            r = where[rows][:, None]
            return x >= r, (x - r) / r
        return pred

    return make(shifted, "fast"), make(roots, "certified"), calls


@pytest.mark.parametrize("guided", [False, True])
@pytest.mark.parametrize("ways", [8, 16, 64])
def test_the_certified_change_is_found_wherever_the_fast_one_errs(guided, ways):
    rng = np.random.default_rng(3)
    roots = 10 ** rng.uniform(-3, 3, 24)
    err = np.concatenate([[0, 1, -1, 3, -4, 5, 17, -40, 300, -2000, 70000, -(1 << 20)],
                          rng.integers(-5000, 5000, 12)])
    fast, certified, calls = _problem(roots, err)
    wrap = (lambda p: p) if guided else (lambda p: (lambda x, r: p(x, r)[0]))
    a, b = search_bits(wrap(fast), np.zeros(roots.size), 1e4 * np.ones(roots.size), ways=ways,
                       certified=wrap(certified), guided=guided)
    assert np.array_equal(b, roots)
    assert np.array_equal(a.view(np.int64) + 1, roots.view(np.int64))
    # the windows and their search ask far fewer calls than halving 2^20 ulp would
    assert calls["certified"] <= 20


def test_an_end_of_the_bracket_keeps_no_claim():
    # the predicate holds all the way: the pair found at the bracket's lower end stands
    roots = np.array([1.0, 2.0])
    fast, certified, _ = _problem(roots, [0, 0])
    lo = np.array([1.5, 2.5])
    a, b = search_bits(lambda x, r: fast(x, r)[0], lo, np.array([3.0, 3.0]),
                       certified=lambda x, r: certified(x, r)[0])
    assert np.array_equal(a, lo) and np.array_equal(b.view(np.int64), lo.view(np.int64) + 1)


def test_the_secant_takes_an_end_where_f_rounds_to_zero():
    # f is 0 on the first 1e-13 relative above each change (a flat trace's last bits): an end of the
    # bracket there still guides the certified steps (even steps took 8 calls, the secant takes 3)
    rng = np.random.default_rng(5)
    roots = 10 ** rng.uniform(-2, 2, 16)
    calls = [0]

    def pred(x, rows):
        calls[0] += 1
        r = roots[rows][:, None]
        f = (x - r) / r
        return x >= r, np.where((f >= 0) & (f < 1e-13), 0.0, f)

    a, b = search_bits(pred, roots * (1 - 1e-11), roots * (1 + 1e-11), ways=8, certified=pred, guided=True,
                       certified_steps=True)
    assert np.array_equal(b, roots) and np.array_equal(a.view(np.int64) + 1, roots.view(np.int64))
    assert calls[0] <= 4
