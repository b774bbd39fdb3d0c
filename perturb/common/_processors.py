"""Processors and worker processes: how many processors this process may run on (the
default number of worker processes of the atlas and of ``make paper``'s scenes, and of
the threads that walk a sweep's lanes), and workers that end with the process that
started them."""

import ctypes
import ctypes.util
import os
import signal
import sys
from functools import partial

__all__ = ["processors", "tied_to_this_process"]


def processors() -> int:
    """The processors this process may run on (its CPU affinity where the system has one)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def tied_to_this_process():
    """An ``initializer`` for a worker pool whose workers end when this process ends,
    even when it is killed (on Linux: the kernel sends them SIGTERM, ``prctl``'s
    PR_SET_PDEATHSIG; elsewhere a pool's own shutdown is all there is)."""
    return partial(_die_with, os.getpid())


_PR_SET_PDEATHSIG = 1


def _die_with(parent: int) -> None:
    if not sys.platform.startswith("linux"):
        return
    libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    if os.getppid() != parent:  # the parent died before the call: nobody would tell us
        os._exit(1)
