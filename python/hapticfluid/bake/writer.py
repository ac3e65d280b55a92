# SPDX-License-Identifier: GPL-3.0-or-later
"""The bake's writer thread: frame n's files are written while the simulation steps frame n+1.

The bake loop steps a frame, reads its state back once (``Simulation.state()``: copies owned by
Python, so the simulation can go on) and hands it over with :meth:`FrameWriter.put`. The
writer thread writes what the job's ``write`` function writes (the frame file, its record, the
checkpoint, the manifest), one frame after the other in frame order, so the order of writes per
frame and across frames is the sequential bake's and a kill leaves what it would have left.

Bounded: at most ``QUEUE_FRAMES`` states wait beside the one being written; ``put`` blocks
while the queue is full, so memory stays at a few frames' states whatever the disk's speed.

Errors: the first exception a write raises stops the writer (later queued frames are dropped,
so no checkpoint ever runs past a frame whose file is missing) and comes back to the bake's
thread from the next ``put``, ``check`` or ``close`` as a BakeError naming the frame.

Only the bake's thread reports: the writer queues what it finished, and the bake's thread
takes it with :meth:`FrameWriter.finished` to call the log and progress callbacks, so callers
see every callback on one thread, as before.
"""

from __future__ import annotations

import queue
import threading
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Optional

from hapticfluid.bake.cache import BakeError

QUEUE_FRAMES = 1  # states waiting beside the one being written (2 frames in flight at most)
_POLL_S = 0.1  # how often a blocked put looks for the writer's error


@dataclass(frozen=True)
class FrameJob:
    frame: int
    substeps: int
    state: Dict[str, Any]  # from Simulation.state(), owned by the job
    step_s: float  # wall time the frame's steps and read-back took
    pressure: Dict[str, Any] = field(default_factory=dict)  # the session's solver figures so far (manifest)


@dataclass(frozen=True)
class FrameWritten:
    frame: int
    substeps: int
    step_s: float
    write_s: float  # wall time of the frame's writes on the writer thread


class FrameWriter:
    """A thread that runs ``write(job)`` for each job put, in order (see the module)."""

    def __init__(self, write: Callable[[FrameJob], None], depth: int = QUEUE_FRAMES,
                 abort_when: Callable[[], bool] = lambda: False) -> None:
        """abort_when: polled by put (while it waits) and by the writer before each job; once it
        returns True, the frames not yet being written are dropped, as close(abort=True) does
        (the bake's 'stop at once', asked from a signal handler that must not take a lock)."""
        if depth < 1:
            raise ValueError(f"depth must be >= 1, got {depth}")
        self._write = write
        self._abort_when = abort_when
        self._jobs: "queue.Queue[Optional[FrameJob]]" = queue.Queue(maxsize=depth)
        self._done: "queue.Queue[FrameWritten]" = queue.Queue()
        self._error: Optional[BakeError] = None
        self._abort = threading.Event()
        self._closed = False
        self._ended = threading.Event()  # set by the thread as its last act (see _end_thread)
        self._thread = threading.Thread(target=self._run, name="hapticfluid-bake-writer", daemon=True)
        self._thread.start()

    def put(self, job: FrameJob) -> None:
        """Queue a frame; blocks while ``depth`` frames wait. Raises the writer's error. Drops
        the frame once abort_when() says so."""
        while True:
            self.check()
            if self._aborted():
                return
            try:
                self._jobs.put(job, timeout=_POLL_S)
                return
            except queue.Full:
                continue

    def check(self) -> None:
        """Raise the writer's error (a BakeError naming the frame), if it had one."""
        if self._error is not None:
            raise self._error

    def _aborted(self) -> bool:
        """close(abort=True) was called, or the owner's abort_when() says so."""
        return self._abort.is_set() or self._abort_when()

    def finished(self) -> List[FrameWritten]:
        """Frames written since the last call, in order (never blocks)."""
        out = []
        while True:
            try:
                out.append(self._done.get_nowait())
            except queue.Empty:
                return out

    def close(self, abort: bool = False) -> None:
        """Wait until every queued frame is written (abort: only the one being written), then
        end the thread. Does not raise the writer's error: call check() after.

        A KeyboardInterrupt (Ctrl-C) while it waits turns the close into an abort and is raised
        once the thread has ended: the writer never outlives the bake. A daemon thread still in
        native code (a frame's write) when the interpreter exits is stopped by pthread_exit,
        whose unwinding through C++ ends the process with std::terminate (exit -6)."""
        if self._closed:
            return
        self._closed = True
        if abort:
            self._abort.set()
        interrupted: Optional[BaseException] = None
        while True:
            try:
                self._end_thread()
                break
            except KeyboardInterrupt as exc:  # stop at once, but only once the thread is gone
                interrupted = exc
                self._abort.set()
        if interrupted is not None:
            raise interrupted

    def _end_thread(self) -> None:
        # Waits on the writer's own "ended" event, not on Thread.is_alive()/join(): a
        # KeyboardInterrupt inside Thread.join() can mark a running thread stopped (CPython's
        # bpo-45274 clean-up releases the lock the thread still holds), and the next join then
        # returns at once while the thread is still writing.
        while not self._ended.is_set():  # the end marker; the writer keeps taking jobs, so this never waits long
            try:
                self._jobs.put(None, timeout=_POLL_S)
                break
            except queue.Full:
                continue
        while not self._ended.wait(_POLL_S):
            pass
        self._thread.join()  # only Python frames are left on the thread

    def _run(self) -> None:
        try:
            self._take_jobs()
        finally:
            self._ended.set()

    def _take_jobs(self) -> None:
        while True:
            job = self._jobs.get()
            if job is None:
                return
            if self._error is not None or self._aborted():
                continue  # dropped: nothing after a failed frame, nothing queued after an abort
            t0 = time.perf_counter()
            try:
                self._write(job)
            except Exception as exc:  # noqa: BLE001 - every failure is the bake's error, with the frame
                err = BakeError(f"writing frame {job.frame} failed ({type(exc).__name__}: {exc}); every frame "
                                "before it is complete with its checkpoint: fix the cause and resume the bake")
                err.__cause__ = exc
                self._error = err
                continue
            self._done.put(FrameWritten(job.frame, job.substeps, job.step_s, time.perf_counter() - t0))
