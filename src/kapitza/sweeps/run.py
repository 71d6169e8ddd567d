"""Run a sweep: chunks of the grid computed serially or on Dask, each written as it finishes."""
from __future__ import annotations

import os
import shutil
import sys
import uuid
from dataclasses import dataclass
from pathlib import Path

from .. import _validate as _v
from .kernel import block_quantities
from .spec import SweepSpec
from .store import create_store, open_store, remove_leftovers, stored_spec, verified_chunks, write_chunk

__all__ = ["compute_chunk", "sweep", "SweepRun"]


@dataclass(frozen=True)
class SweepRun:
    """What a call of :func:`sweep` did.

    Attributes
    ----------
    store : Path
    total : int
        Chunks of the grid.
    computed : int
        Chunks computed by this call (on a resume: only the unfinished ones).
    skipped : int
        Chunks found finished in the store, their data checked against their checksums, and not
        recomputed.
    damaged : tuple of (int, int)
        Chunks flagged finished whose data was missing, unreadable or not what was written:
        recomputed (they count in ``computed``).
    notes : tuple of str
        Store-wide repairs made before resuming (a lost coordinate, unreadable flags).

    Examples
    --------
    >>> import os, shutil, tempfile
    >>> from kapitza.sweeps import SweepSpec, sweep
    >>> spec = SweepSpec.window((0.3, 0.9), (0.2, 0.4), (4, 3), quantities=("linear",), chunk=2)
    >>> folder = tempfile.mkdtemp()
    >>> run = sweep(spec, os.path.join(folder, "map.zarr"), serial=True, progress=False)
    >>> run.total, run.computed, run.skipped, run.damaged
    (4, 4, 0, ())
    >>> run.open().zone.values
    array([[ 0,  0, -1, -1],
           [-1,  0,  0, -1],
           [-1,  0,  0, -1]], dtype=int16)
    >>> shutil.rmtree(folder)
    """

    store: Path
    total: int
    computed: int
    skipped: int
    damaged: tuple = ()
    notes: tuple = ()

    def open(self):
        """The result as an :class:`xarray.Dataset`."""
        from .store import open_sweep

        return open_sweep(self.store)


def compute_chunk(spec: SweepSpec, iy: int, ix: int) -> dict:
    """Every variable of chunk ``(iy, ix)``: a pure function of its arguments (the unit of work).

    Parameters
    ----------
    spec : SweepSpec
    iy, ix : int
        The chunk's row and column in the grid of chunks (:attr:`SweepSpec.chunk_shape`).

    Returns
    -------
    dict of str to ndarray
        Each variable of :attr:`SweepSpec.variables`, of the chunk's shape.

    Raises
    ------
    KapitzaValueError
        If ``spec`` is not a :class:`SweepSpec` or ``(iy, ix)`` is not a chunk of its grid.

    Examples
    --------
    >>> from kapitza.sweeps import SweepSpec, compute_chunk
    >>> spec = SweepSpec.window((0.3, 0.9), (0.2, 0.4), (4, 3), quantities=("linear",), chunk=2)
    >>> values = compute_chunk(spec, 0, 0)
    >>> sorted(values)
    ['growth', 'margin', 'stable', 'zone']
    >>> values["zone"]
    array([[ 0,  0],
           [-1,  0]], dtype=int16)
    """
    if not isinstance(spec, SweepSpec):
        raise _v.KapitzaValueError(f"spec must be a kapitza.sweeps.SweepSpec; got {type(spec).__name__}")
    ny, nx = spec.chunk_shape
    iy, ix = (_v.bounded_count(name, i, 2**61) for name, i in (("iy", iy), ("ix", ix)))  # whole numbers >= 0
    for name, i, n in (("iy", iy, ny), ("ix", ix, nx)):
        if i >= n:
            raise _v.KapitzaValueError(f"{name} must satisfy 0 <= {name} < {n} (the chunks of this sweep); got {i}")
    ys, xs = spec.chunk_slices(iy, ix)
    return block_quantities(spec.x[xs], spec.y[ys], plane=spec.plane, l=spec.l, g=spec.g, drive=spec.drive,
                            periods=spec.periods, tol=spec.tol, quantities=spec.quantities,
                            directions=spec.directions, basin_resolution=spec.basin_resolution,
                            accuracy=spec.accuracy, floor=spec.floor, c=spec.c)


def _prepare(spec, store, resume):
    import zarr

    store = Path(store)
    remove_leftovers(store)
    if not (store.exists() or store.is_symlink()):
        return create_store(store, spec)
    if not resume:
        raise _v.KapitzaValueError(f"store must be a new path, or resumed (resume=True, --resume); got "
                                   f"{str(store)!r}, which exists")
    old = stored_spec(store)
    if old != spec:
        diff = [k for k, v in spec.as_dict().items() if old.as_dict()[k] != v]
        raise _v.KapitzaValueError(f"resume must use the store's own settings; {str(store)!r} differs in "
                                   f"{', '.join(diff)}")
    grp = open_store(store)
    if "chunk_done" not in grp and "chunk_checksum" not in grp:
        # An older kapitza built the store in place and was interrupted before its done flags were
        # written: no chunk was computed yet, so the store is rebuilt from the same settings.
        aside = store.parent / f".{store.name}.replaced-{os.getpid()}-{uuid.uuid4().hex[:8]}"  # see remove_leftovers
        os.rename(store, aside)
        grp = create_store(store, spec)
        shutil.rmtree(aside, ignore_errors=True)
        return grp
    if not (store / ".zmetadata").exists():  # copied without it: readers want it back
        zarr.consolidate_metadata(str(store))
        grp = open_store(store)
    return grp


def sweep(spec: SweepSpec, store, *, resume=False, serial=False, workers=None, scheduler=None, client=None,
          progress=True, on_chunk=None) -> SweepRun:
    """Compute ``spec`` into the Zarr store ``store``, chunk by chunk.

    Parameters
    ----------
    spec : SweepSpec
    store : path
        Zarr store (a folder) to create, or to complete with ``resume=True``.
    resume : bool
        Continue a store made by an interrupted sweep with the same ``spec``: every chunk flagged
        finished is read back and checked against its checksum; the rest, and any whose data is
        missing or damaged, are computed (``SweepRun.damaged`` names those).
    serial : bool
        Compute in this process, without Dask (same numbers bit for bit).
    workers : int, optional
        Workers of the local Dask cluster (processes, one thread each); default: the CPU count.
    scheduler : str, optional
        Address of an existing Dask scheduler (``tcp://host:8786``) instead of a local cluster.
    client : distributed.Client, optional
        An existing client (overrides ``workers`` and ``scheduler``).
    progress : bool
        Show a progress bar (chunks done, rate, time left) on stderr.
    on_chunk : callable, optional
        ``on_chunk(done, total)`` after each chunk is written.

    Returns
    -------
    SweepRun

    Raises
    ------
    ValueError
        If the store exists and ``resume`` is not set, ``resume`` meets a store of another ``spec``,
        or ``workers`` is out of range.

    Examples
    --------
    A tiny map of the exact linear verdicts, computed in this process; a second call resumes and
    finds every chunk done:

    >>> import os, shutil, tempfile
    >>> from kapitza.sweeps import SweepSpec, sweep
    >>> spec = SweepSpec.window((0.3, 0.9), (0.2, 0.4), (4, 3), quantities=("linear",), chunk=2)
    >>> folder = tempfile.mkdtemp()
    >>> store = os.path.join(folder, "map.zarr")
    >>> sweep(spec, store, serial=True, progress=False).computed
    4
    >>> sweep(spec, store, serial=True, progress=False, resume=True).skipped
    4
    >>> shutil.rmtree(folder)
    """
    if not isinstance(spec, SweepSpec):
        raise _v.KapitzaValueError(f"spec must be a SweepSpec; got {type(spec).__name__}")
    grp = _prepare(spec, store, resume)
    check = verified_chunks(grp, spec)
    done = check.done
    todo = [c for c in spec.all_chunks() if not done[c]]
    total = len(spec.all_chunks())
    skipped = total - len(todo)
    from tqdm import tqdm

    bar = tqdm(total=total, initial=skipped, unit="chunk", desc="kapitza sweep", disable=not progress,
               file=sys.stderr, dynamic_ncols=True)
    count = skipped

    def finished(iy, ix, values):
        nonlocal count
        write_chunk(grp, spec, iy, ix, values)
        count += 1
        bar.update(1)
        if on_chunk is not None:
            on_chunk(count, total)

    try:
        if serial or not todo:
            for iy, ix in todo:
                finished(iy, ix, compute_chunk(spec, iy, ix))
        else:
            _run_dask(spec, todo, finished, workers, scheduler, client)
    finally:
        bar.close()
    return SweepRun(store=Path(store), total=total, computed=len(todo), skipped=skipped,
                    damaged=tuple(check.damaged), notes=tuple(check.notes))


def _run_dask(spec, todo, finished, workers, scheduler, client):
    from distributed import Client, LocalCluster, as_completed

    own_cluster = own_client = None
    try:
        if client is None:
            if scheduler is not None:
                client = own_client = Client(scheduler)
            else:
                n = _v.workers(workers if workers is not None else (os.cpu_count() or 1), len(todo))
                own_cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                           dashboard_address=":0", silence_logs=40)
                client = own_client = Client(own_cluster)
        token = uuid.uuid4().hex[:12]  # this call's tasks: never mistaken for another sweep's
        futures = {client.submit(compute_chunk, spec, iy, ix, key=f"kapitza-sweep-{token}-{iy}-{ix}", pure=False,
                                 retries=3): (iy, ix) for iy, ix in todo}
        for fut in as_completed(futures):
            iy, ix = futures.pop(fut)
            finished(iy, ix, fut.result())
            fut.release()
    finally:
        if own_client is not None:
            own_client.close()
        if own_cluster is not None:
            own_cluster.close()
