"""How many processors this process may run on: the default number of worker processes
(the atlas, ``make paper``'s scenes) and of the threads that walk a sweep's lanes."""

import os


def processors() -> int:
    """The processors this process may run on (its CPU affinity where the system has one)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1
