# SPDX-License-Identifier: Apache-2.0
"""okid.AmbientIdentifier, the streaming output-only identifier (docs/ambient.md, "Streaming"):
against okid.identify_ambient on the same record, its fixed memory over a long record pushed in
pieces, non-finite samples, and its refusals.

Equality: identify_ambient removes each channel's mean (summed in double in sample order) before
the sums; the stream sums what it is given. On a record of integers whose every column sums to
exactly zero that mean is exactly 0, so both sum the same values in the same batches (how the
record is cut into calls changes no bit: okid/ambient.h, okid_ambient_push_block) and the results
are equal bit for bit. On a record with a mean, the stream gets y minus NumPy's mean (pairwise
summation), which may differ from the C mean in its last bits; see
test_a_record_with_a_mean_to_round_off for the tolerance.
"""
import copy
import pickle
import tracemalloc
import warnings

import numpy as np
import pytest

import okid
from test_ambient import DT, ambient_record, exact_modes

L, ORDER = 20, 4


def integer_record(samples=20000, seed=3):
    """The simulated paper record in integer steps of 1e-3 of its RMS, every column summing to 0 exactly."""
    y = ambient_record(samples=samples, seed=seed)
    q = np.round(y / (1e-3 * y.std(axis=0)))
    q -= np.round(q.mean(axis=0))
    q[-1] -= q.sum(axis=0)  # integers below 2^53: every sum is exact
    assert np.all(q.sum(axis=0) == 0)
    return np.ascontiguousarray(q)


def assert_same_result(a, b):
    assert a.order == b.order and a.samples == b.samples and a.pairs == b.pairs and a.references == b.references
    assert a.hankel_rows == b.hankel_rows and a.warnings == b.warnings and a.segments_used == b.segments_used
    for name in ("A", "C", "G", "correlations", "singular_values", "frequencies_hz", "damping_ratios"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert a.realization_condition == b.realization_condition
    assert [m.mpc for m in a.modes] == [m.mpc for m in b.modes]
    for name in ("frequency_std", "damping_std"):
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None) == (y is None), name
        if x is not None:
            np.testing.assert_array_equal(x, y, err_msg=name)


@pytest.mark.parametrize("segments", [0, 4])
def test_pieces_give_identify_ambient_bit_for_bit(segments):
    y = integer_record()
    whole = okid.identify_ambient(y, DT, hankel_rows=L, order=ORDER, segments=segments)
    amb = okid.AmbientIdentifier(2, DT, hankel_rows=L, order=ORDER, segments=segments)
    before = y.copy()
    cuts = [0, 1, 700, 701, 5000, 13333, len(y)]  # one sample, uneven blocks, a batch boundary crossed anywhere
    for a, b in zip(cuts[:-1], cuts[1:]):
        assert amb.push(y[a:b] if b - a > 1 else y[a]) == b - a
    assert np.array_equal(y, before)  # the caller's array is never written
    assert amb.progress == okid.AmbientProgress(samples=len(y), rejected=0, samples_needed=2 * L + 1)
    res = amb.identify()
    assert isinstance(res, okid.AmbientResult) and res.band_hz == 0 and res.poles is None
    assert_same_result(res, whole)
    assert_same_result(amb.identify(), res)  # identify changes no sum


def test_a_record_with_a_mean_to_round_off():
    """y with a mean, the stream fed y - mean: the sums differ only by the two means' rounding.

    |mean| is about 16 rms here. The C mean (a sum in sample order) is within N u |mean| of the
    exact one in the worst case (N = 20000, u = 1.1e-16: 2.2e-12 relative), NumPy's (pairwise)
    within log2(N) u; each sample then moves by delta <= 2.2e-12 |mean| = 3.5e-11 rms, each R(k)
    by at most 2 delta rms (7e-11 of R(0)), and the modes by that times the realization's
    condition (2.9, realization_condition) for these well-separated pairs: 2e-10. The check allows
    1e-9. Measured on this record: 0 (the two means agreed to the bit)."""
    y = ambient_record(samples=20000, seed=5) + np.array([0.3, -0.2]) * 3 / 0.1
    whole = okid.identify_ambient(y, DT, hankel_rows=L, order=ORDER)
    amb = okid.AmbientIdentifier(2, DT, hankel_rows=L, order=ORDER)
    amb.push(y - y.mean(axis=0))
    res = amb.identify()
    np.testing.assert_allclose(res.correlations, whole.correlations, rtol=0,
                               atol=1e-9 * np.abs(whole.correlations).max())
    np.testing.assert_allclose(res.frequencies_hz, whole.frequencies_hz, rtol=1e-9)
    np.testing.assert_allclose(res.damping_ratios, whole.damping_ratios, rtol=1e-9)


def test_a_long_record_in_pieces_takes_fixed_memory():
    """200 000 samples in 100 pieces: the workspace stays its size, the pushes allocate nothing that
    grows with the record (tracemalloc sees NumPy's and Python's allocations; a copy of the record
    would be 3.2 MB, one piece's 32 KB), and the result is one push's, bit for bit."""
    y = integer_record(samples=200000, seed=8)
    amb = okid.AmbientIdentifier(2, DT, hankel_rows=L, order=ORDER)
    bytes0 = amb.workspace_bytes
    assert bytes0 > 0
    tracemalloc.start()
    base = tracemalloc.get_traced_memory()[0]
    for piece in np.split(y, 100):  # C-contiguous row slices: pushed without a copy
        amb.push(piece)
    grown = tracemalloc.get_traced_memory()[1] - base
    tracemalloc.stop()
    assert grown < 32 * 1024, f"the pushes allocated {grown} bytes"
    assert amb.workspace_bytes == bytes0
    one = okid.AmbientIdentifier(2, DT, hankel_rows=L, order=ORDER)
    one.push(y)
    assert one.workspace_bytes == bytes0
    assert_same_result(amb.identify(), one.identify())


def test_non_finite_samples_are_a_gap_as_identify_ambient_has_them():
    y = ambient_record(samples=8000)
    y -= y.mean(axis=0)
    y[100, 1] = np.nan
    amb = okid.AmbientIdentifier(2, DT, hankel_rows=10, order=ORDER, references=[1])
    with pytest.warns(okid.NonFiniteSampleWarning, match="1 of 8000 samples"):
        assert amb.push(y) == 7999
    assert amb.progress.samples == 7999 and amb.progress.rejected == 1
    res = amb.identify()
    assert res.references == (1,) and res.G.shape == (4, 1)
    assert res.samples == 7999 and res.pairs == (100 - 20) + (8000 - 101 - 20)  # no product spans the gap


def test_refusals_and_reset():
    with pytest.raises(okid.BadOrderError, match="order = 99: valid 0..40"):
        okid.AmbientIdentifier(2, DT, hankel_rows=20, order=99)
    with pytest.raises(okid.BadParameterError, match="reference_channels = 2: valid 0..1"):
        okid.AmbientIdentifier(2, DT, references=[2])
    with pytest.raises(okid.BadSizeError, match="hankel_rows = 0: valid 1"):
        okid.AmbientIdentifier(2, DT, hankel_rows=0)
    with pytest.raises(okid.BadSizeError, match="num_outputs = 0"):
        okid.AmbientIdentifier(0, DT)
    with pytest.raises(okid.BadParameterError, match="sensing = 'strain'"):
        okid.AmbientIdentifier(2, DT, sensing="strain")
    amb = okid.AmbientIdentifier(2, DT, hankel_rows=L, order=ORDER)
    with pytest.raises(okid.BadSizeError, match=r"shape \(2, 100\).*pass y.T"):
        amb.push(np.zeros((2, 100)))
    with pytest.raises(okid.BadSizeError, match=r"expected \(samples, 2\)"):
        amb.push(np.zeros((10, 3)))
    amb.push(integer_record(samples=2 * L, seed=1))  # one sample short of a pair at lag 2L
    with pytest.raises(okid.NotEnoughDataError, match="40 samples pushed: no pair at lag 2 hankel_rows = 40"):
        amb.identify()
    amb.push(np.ones(2))
    amb.identify()
    amb.reset()
    assert amb.progress.samples == 0
    with pytest.raises(okid.NotEnoughDataError):
        amb.identify()
    calls = []
    amb.push(integer_record(samples=1000, seed=2), progress=lambda done, total: calls.append((done, total)))
    assert calls[-1] == (1000, 1000)
    with pytest.raises(TypeError, match="cannot be pickled"):
        pickle.dumps(amb)
    with pytest.raises(TypeError, match="cannot be copied"):
        copy.copy(amb)
    with amb:
        pass
    with pytest.raises(ValueError, match="closed"):
        amb.push(np.ones(2))


def test_a_read_only_block_is_pushed_as_is():
    y = integer_record(samples=2000)
    y.flags.writeable = False
    amb = okid.AmbientIdentifier(2, DT, hankel_rows=L, order=ORDER)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert amb.push(y) == 2000
    assert amb.identify().samples == 2000


def test_order_zero_gives_the_physical_modes_of_identify_ambient():
    """order 0 (the default): the physical modes of the one Hankel size, as identify_ambient gives them
    with hankel_rows given, and the model at the lowest order that holds them (okid/ambient.h,
    okid_ambient_identify_order: the same sums, no second pass). The two take their tables from
    identifiers whose workspaces hold different largest orders (the stream's L m, the batch's 60
    at most), so the realization's leading dimensions differ: a kernel whose path depends on them
    moves the modes at round-off times the realization's condition (about 3 here), hence rtol 1e-9,
    as test_ambient_modes allows the same comparison. The exact modes (NumPy's eigenvalues of the
    continuous plant) are the independent check: within 2 % in frequency, the selection's own gate.
    This record (20 000 samples at 0.05 s) holds the 0.50 Hz mode; the 1.05 Hz one (damped 33 %)
    is selected by neither path at L = 20, 40 or 60 (measured), nor by identify_ambient's own L."""
    y = integer_record()
    whole = okid.identify_ambient(y, DT, hankel_rows=L)
    amb = okid.AmbientIdentifier(2, DT, hankel_rows=L)
    amb.push(y)
    res = amb.identify()
    assert all(isinstance(md, okid.SelectedMode) for md in res.modes)
    assert len(res.modes) == len(whole.modes) >= 1
    np.testing.assert_allclose([md.frequency_hz for md in res.modes], [md.frequency_hz for md in whole.modes],
                               rtol=1e-9)
    np.testing.assert_allclose([md.damping_ratio for md in res.modes], [md.damping_ratio for md in whole.modes],
                               rtol=1e-9)
    exact_f = np.array([f for f, _ in exact_modes()])
    for md in res.modes:
        f = exact_f[np.argmin(np.abs(exact_f - md.frequency_hz))]
        assert abs(md.frequency_hz - f) <= 0.02 * f, (md.frequency_hz, f)
    assert res.order == whole.order and res.A.shape == (res.order, res.order)
    assert res.chosen["order"]["reason"] == whole.chosen["order"]["reason"]
    assert res.chosen["hankel_rows"] == {"value": L, "chosen": False, "reason": "given"}
    assert list(res.chosen["selection_band_hz"]) == [0, 0.8 * 0.5 / DT]  # a stream has no 5 % frequency
    assert [p.verdict for p in res.poles].count("physical") == sum(1 for md in res.modes if md.is_pair)
    assert not res.warnings & okid.WarningFlag.NO_PHYSICAL_MODE
    given = okid.AmbientIdentifier(2, DT, hankel_rows=L, order=res.order)  # the order given: no selection
    given.push(y)
    fixed = given.identify()
    assert fixed.poles is None and fixed.chosen is None
    np.testing.assert_allclose(fixed.frequencies_hz, [p.frequency_hz for p in res.poles], rtol=1e-9)


def test_no_physical_mode_says_so():
    """A Hankel matrix too small for one pair (L = 1 with one reference: order 1 at most) selects
    nothing: no modes, the largest-gap model's poles each with its verdict, and the warning flag."""
    y = integer_record(samples=4000)
    amb = okid.AmbientIdentifier(2, DT, hankel_rows=1, references=[0])
    amb.push(y)
    res = amb.identify()
    assert res.modes == () and res.order == 1
    assert res.warnings & okid.WarningFlag.NO_PHYSICAL_MODE
    assert res.chosen["order"]["reason"] == "no physical mode: the largest singular-value gap"
    assert all(p.verdict == "rejected" for p in res.poles)
