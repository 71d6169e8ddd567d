"""Sweep stores that cannot lie: interrupted at any moment, or damaged on disk, a resumed map equals an
uninterrupted one value by value, and what was damaged is named; what cannot be resumed is refused in
one line. The interruptions are real (subprocesses killed with SIGKILL, SIGINT or SIGTERM), timed by
what appears on disk, never by the clock."""
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

pytest.importorskip("distributed")
pytest.importorskip("zarr")
pytest.importorskip("xarray")

from kapitza.sweeps import SweepSpec, open_store, open_sweep, sweep
from kapitza.sweeps.store import create_store, done_chunks

from cli_util import assert_one_line_error, run

# 30 chunks of 2 x 2 points: long enough after any marker that a poll every few ms sees the run still going
ARGS = ["sweep", "--eps", "0.15", "0.9", "--mu", "0.05", "0.7", "--resolution", "12", "10", "--chunk", "2",
        "--periods", "60", "--floor", "0.01", "--quantities", "tilt,linear", "--quiet"]
SPEC = dict(x_range=(0.15, 0.9), y_range=(0.05, 0.7), resolution=(12, 10), periods=60, floor=0.01,
            quantities=("tilt", "linear"), chunk=2)
CHUNKS = 30
DEADLINE = 600.0  # seconds: generous, the machine may be loaded many times over


def spec():
    return SweepSpec.window(**SPEC)


def arrays(path):
    ds = open_sweep(path).load()
    return {v: ds[v].values for v in spec().variables}


@pytest.fixture(scope="module")
def reference_store(tmp_path_factory):
    path = tmp_path_factory.mktemp("ref") / "ref.zarr"
    sweep(spec(), path, serial=True, progress=False)
    return path


@pytest.fixture(scope="module")
def reference(reference_store):
    return arrays(reference_store)


def assert_equal_to(path, ref):
    got = arrays(path)
    assert got.keys() == ref.keys()
    for k in ref:
        assert got[k].dtype == ref[k].dtype, k
        assert np.array_equal(got[k], ref[k]), k  # value by value; the reference has no NaN and no fill
    assert int(done_chunks(open_store(path)).sum()) == CHUNKS


def done_count(path):
    try:
        return int(done_chunks(open_store(path)).sum())
    except Exception:  # not there yet, or a flag being written at this instant
        return -1


def leftovers(folder):
    return [p.name for p in folder.iterdir() if ".creating-" in p.name or ".replaced-" in p.name]


# ------------------------------------------------------------------ fill values
def test_points_not_computed_read_as_fill_values_no_result_can_take(tmp_path):
    s = SweepSpec.window((0.2, 0.9), (0.05, 0.6), (5, 4), periods=5, quantities=("tilt", "linear"), chunk=2)
    create_store(tmp_path / "f.zarr", s)
    ds = open_sweep(tmp_path / "f.zarr").load()
    assert ds.zone.dtype == np.int16 and np.all(ds.zone.values == -2)  # -1 is unstable, n >= 0 a zone
    assert ds.stable.dtype == np.int8 and np.all(ds.stable.values == -1)  # results are 0 or 1
    assert np.all(np.isnan(ds.max_safe_tilt.values)) and np.all(np.isnan(ds.margin.values))
    assert ds.zone.attrs["_FillValue"] == -2


def test_a_lost_chunk_file_reads_as_fill_not_as_zone_0(tmp_path):
    s = SweepSpec.window((0.2, 0.9), (0.05, 0.6), (5, 4), periods=5, quantities=("tilt", "linear"), chunk=2)
    sweep(s, tmp_path / "f.zarr", serial=True, progress=False)
    (tmp_path / "f.zarr" / "zone" / "0.0").unlink()
    zone = open_sweep(tmp_path / "f.zarr").zone.values
    assert np.all(zone[:2, :2] == -2)


# ------------------------------------------------------------------ damage on disk
@pytest.fixture
def full_store(reference_store, tmp_path):
    """A finished store of the sweep ``ARGS``, to damage."""
    path = tmp_path / "m.zarr"
    shutil.copytree(reference_store, path)
    return path


def test_resume_recomputes_lost_and_truncated_chunks_and_names_them(full_store, tmp_path, capsys, reference):
    path = full_store
    (path / "zone" / "0.1").unlink()  # a partial copy, a sync tool
    (path / "max_safe_tilt" / "2.3").unlink()
    with open(path / "growth" / "4.5", "r+b") as f:  # a disk error: a truncated chunk file
        f.truncate(7)
    code, _, err = run([*ARGS, "--serial", "--no-figure", "--out", str(path), "--resume"], capsys)
    assert code == 0, err
    assert "Traceback" not in err and "Warning" not in err
    assert "3 chunk(s) flagged done had missing or damaged data" in err
    assert "(0, 1), (2, 3), (4, 5)" in err
    assert f"computed 3 of {CHUNKS} chunks ({CHUNKS - 3} already done)" in err
    assert_equal_to(path, reference)


def test_a_chunk_overwritten_with_other_values_is_caught_by_its_checksum(full_store, tmp_path, capsys, reference):
    path = full_store
    grp = open_store(path)
    grp["max_safe_tilt"][0:2, 0:2] = grp["max_safe_tilt"][0:2, 0:2] * (1 + 1e-12)  # readable, plausible, wrong
    code, _, err = run([*ARGS, "--serial", "--no-figure", "--out", str(path), "--resume"], capsys)
    assert code == 0, err
    assert "were recomputed: (0, 0)" in err
    assert_equal_to(path, reference)


@pytest.mark.filterwarnings("error")
def test_a_store_copied_without_zmetadata_resumes_without_a_warning(full_store, tmp_path, capsys, reference):
    path = full_store
    (path / ".zmetadata").unlink()
    code, _, err = run([*ARGS, "--serial", "--no-figure", "--out", str(path), "--resume"], capsys)
    assert code == 0, err
    assert "Warning" not in err and f"computed 0 of {CHUNKS} chunks ({CHUNKS} already done)" in err
    assert (path / ".zmetadata").exists()
    assert_equal_to(path, reference)


def test_a_store_copied_without_any_dot_file_is_refused_in_one_line(full_store, tmp_path, capsys):
    path = full_store
    for dirpath, _, files in os.walk(path):
        for f in files:
            if f.startswith("."):
                os.unlink(os.path.join(dirpath, f))
    code, _, err = run([*ARGS, "--serial", "--no-figure", "--out", str(path), "--resume"], capsys)
    assert_one_line_error(code, err, str(path), "no Zarr metadata", "delete it")


def test_unreadable_done_flags_recompute_every_chunk(full_store, tmp_path, capsys, reference):
    path = full_store
    with open(path / "chunk_done" / "0.0", "r+b") as f:
        f.truncate(5)
    code, _, err = run([*ARGS, "--serial", "--no-figure", "--out", str(path), "--resume"], capsys)
    assert code == 0, err
    assert "done flags or checksums unreadable" in err and f"computed {CHUNKS} of {CHUNKS}" in err
    assert_equal_to(path, reference)


def _as_older_store(path, drop):
    """The store as an older kapitza left it: without the arrays ``drop``."""
    import zarr

    for name in drop:
        shutil.rmtree(path / name)
    zarr.consolidate_metadata(str(path))


def test_an_older_store_without_checksums_is_explained_in_one_line(full_store, tmp_path, capsys):
    path = full_store
    _as_older_store(path, ["chunk_checksum"])
    code, _, err = run([*ARGS, "--serial", "--no-figure", "--out", str(path), "--resume"], capsys)
    assert_one_line_error(code, err, "older kapitza", "checksums", "new store")


def test_an_older_store_whose_creation_was_interrupted_is_rebuilt(full_store, tmp_path, capsys, reference):
    """An older kapitza created the store in place; killed before its done flags existed, nothing in it
    was computed (the KeyError: 'chunk_done' of old), so resuming rebuilds it from its settings."""
    path = full_store
    _as_older_store(path, ["chunk_checksum", "chunk_done"])
    code, _, err = run([*ARGS, "--serial", "--no-figure", "--out", str(path), "--resume"], capsys)
    assert code == 0, err
    assert f"computed {CHUNKS} of {CHUNKS} chunks (0 already done)" in err
    assert_equal_to(path, reference)
    assert leftovers(tmp_path) == []


def test_a_path_that_is_not_a_store_is_refused_in_one_line(tmp_path, capsys):
    (tmp_path / "m.zarr").mkdir()
    (tmp_path / "m.zarr" / "notes.txt").write_text("mine")
    code, _, err = run([*ARGS, "--serial", "--no-figure", "--out", str(tmp_path / "m.zarr"), "--resume"], capsys)
    assert_one_line_error(code, err, "no Zarr metadata")
    assert (tmp_path / "m.zarr" / "notes.txt").read_text() == "mine"  # never deleted for the user


# ------------------------------------------------------------------ real interruptions
def _start(path, extra=()):
    cmd = [sys.executable, "-m", "kapitza", *ARGS, "--out", str(path), *extra]
    return subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)


def _interrupt_when(proc, ready, sig):
    """Send ``sig`` to the command (and every process it started) as soon as ``ready()`` holds; return
    whether the command was still running then."""
    t0 = time.monotonic()
    try:
        while proc.poll() is None and not ready():
            assert time.monotonic() - t0 < DEADLINE, "the marker never appeared"
            time.sleep(0.002)
        running = proc.poll() is None
        if running:
            os.killpg(proc.pid, sig)
        proc.wait(timeout=DEADLINE)
        return running
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def _creating(path):
    """The store is being created: its temporary folder or (an older layout) the store itself is there."""
    return lambda: path.exists() or any(".creating-" in n for n in os.listdir(path.parent))


def _resume_equals(path, capsys, reference, extra=("--serial",)):
    code, _, err = run([*ARGS, "--no-figure", "--out", str(path), "--resume", *extra], capsys)
    assert code == 0, err
    assert "Traceback" not in err
    assert_equal_to(path, reference)
    assert leftovers(path.parent) == []


def _after_kill(path):
    """What a kill may leave: nothing at the path, or a store that opens and names its settings."""
    if path.exists():
        from kapitza.sweeps.store import stored_spec

        assert stored_spec(path) == spec()


def test_sigkill_while_the_store_is_created_leaves_nothing_or_a_resumable_store(tmp_path, capsys, reference):
    path = tmp_path / "c.zarr"
    proc = _start(path, ["--serial", "--no-figure"])
    _interrupt_when(proc, _creating(path), signal.SIGKILL)
    _after_kill(path)
    _resume_equals(path, capsys, reference)


def test_sigkill_between_chunks_resumes_to_the_same_map(tmp_path, capsys, reference):
    path = tmp_path / "k.zarr"
    for _ in range(5):  # killed after the marker unless the run finished first (a starved poll): again
        if path.exists():
            shutil.rmtree(path)
        proc = _start(path, ["--serial", "--no-figure"])
        if _interrupt_when(proc, lambda: done_count(path) >= 3, signal.SIGKILL) and done_count(path) < CHUNKS:
            break
    done = done_count(path)
    assert 3 <= done < CHUNKS
    code, _, err = run([*ARGS, "--serial", "--no-figure", "--out", str(path), "--resume"], capsys)
    assert code == 0, err
    assert f"computed {CHUNKS - done} of {CHUNKS} chunks ({done} already done)" in err
    assert_equal_to(path, reference)


MOMENTS = ["creating", "mid-chunk", "between chunks", "final write"]
SIGNALS = [signal.SIGKILL, signal.SIGINT, signal.SIGTERM]


@pytest.mark.slow
@pytest.mark.parametrize("trial", range(12))
def test_interrupted_at_a_random_moment_resumes_to_the_same_map(trial, tmp_path, capsys, reference):
    """Twelve trials: a signal and a moment drawn at random (seeded), on Dask or serially; the kill is
    timed by the store (its temporary folder, its done flags), then delayed by a random few ms."""
    rng = np.random.default_rng(trial)
    sig = SIGNALS[trial % 3]
    moment = MOMENTS[(trial // 3) % 4]
    extra = ["--serial"] if rng.random() < 0.5 else ["--workers", "2"]
    path = tmp_path / "r.zarr"
    nc = tmp_path / "r.nc"
    proc = _start(path, [*extra, "--netcdf", str(nc)])
    k = int(rng.integers(1, CHUNKS - 5))
    ready = {"creating": _creating(path),
             "mid-chunk": lambda: done_count(path) >= k,
             "between chunks": lambda: done_count(path) >= k,
             "final write": lambda: done_count(path) >= CHUNKS}[moment]
    delay = {"creating": 0.0, "mid-chunk": rng.uniform(0.0, 0.05), "between chunks": 0.0,
             "final write": rng.uniform(0.0, 0.5)}[moment]

    def marker():
        if not ready():
            return False
        time.sleep(delay)
        return True

    _interrupt_when(proc, marker, sig)
    _after_kill(path)
    if not path.exists():
        assert leftovers(tmp_path) == [] or sig == signal.SIGKILL or sig == signal.SIGTERM
    _resume_equals(path, capsys, reference, extra)


def test_leftovers_of_a_dead_creator_are_removed_and_nothing_else(tmp_path):
    from kapitza.sweeps.store import remove_leftovers

    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait()
    names = [f".my-map.zarr.creating-{gone.pid}-abcd", f".my-map.zarr.replaced-{gone.pid}-ef01",
             f".my-map.zarr.creating-{os.getpid()}-live", ".other.zarr.creating-1-x", "my-map.zarr.creating-1-x"]
    for n in names:
        (tmp_path / n).mkdir()
    remove_leftovers(tmp_path / "my-map.zarr")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(names[2:])  # a live creator's, another store's
