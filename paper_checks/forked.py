"""Jobs run one after another in a child process forked at once (``ForkedJobs``).

`make paper` runs the scenes that need no compiled kernels this way, while its main
process loads the kernels, before it forks the workers that need them: the workers
then find the kernels loaded, and these scenes are done on the processor that would
otherwise wait for the loading.
"""

from __future__ import annotations

import multiprocessing
import pickle
import sys
import traceback
from collections.abc import Callable

from perturb.common import tied_to_this_process

__all__ = ["ForkedJobs", "forks"]


def forks() -> bool:
    """Whether child processes are forked here (Linux): they start at once with what
    this process has imported and loaded; elsewhere they would import it all again."""
    return sys.platform.startswith("linux")


class RemoteTraceback(Exception):
    """The traceback of an error raised in the child process, as text."""


class ForkedJobs:
    """``function(*arguments)`` for each ``(name, arguments)`` of ``jobs``, in that order,
    in one child process forked now.

    ``result(name)`` waits for a job's result, or raises its error (with the child's
    traceback as its cause), as ``Future.result()`` does; ``future(name)`` is an object
    with that ``result()``. The results come back pickled through a pipe. No thread is
    started in this process, so that a process pool forked from it later starts from
    one thread.
    """

    def __init__(self, function: Callable, jobs: dict[str, tuple]) -> None:
        context = multiprocessing.get_context("fork")
        self._receiver, sender = context.Pipe(duplex=False)
        self._process = context.Process(target=_run_and_send,
                                        args=(sender, function, jobs, tied_to_this_process()),
                                        daemon=True)
        self._process.start()
        sender.close()  # the child's end: the pipe ends (EOFError) when the child does
        self._received: dict[str, tuple[bool, object]] = {}
        self._ended = False

    def future(self, name: str) -> _Pending:
        return _Pending(self, name)

    def result(self, name: str):
        while name not in self._received:
            if not self._receive():
                raise RuntimeError(f"the forked process ended (exit code "
                                   f"{self._process.exitcode}) without the result of "
                                   f"{name!r}")
        done, value = self._received[name]
        if not done:
            error, text = value
            raise error from RemoteTraceback(text)
        return value

    def join(self) -> None:
        """Receive the results not asked for yet (the child waits until a result is
        read when it fills the pipe), and wait for the child process to end."""
        while self._receive():
            pass

    def _receive(self) -> bool:
        """Receive the next result; False once the child has ended (and is joined, and
        the pipe closed)."""
        if self._ended:
            return False
        try:
            key, done, value = self._receiver.recv()
        except EOFError:
            self._process.join()
            self._receiver.close()
            self._ended = True
            return False
        self._received[key] = done, value
        return True


class _Pending:
    """One job of a ``ForkedJobs``, waited for as a ``Future``."""

    def __init__(self, jobs: ForkedJobs, name: str) -> None:
        self._jobs, self._name = jobs, name

    def result(self):
        return self._jobs.result(self._name)


def _portable(error: Exception, text: str) -> Exception:
    """``error`` if it comes back whole from pickling (some do not: an exception whose
    __init__ needs more than its args), else a RuntimeError with its last line."""
    try:
        pickle.loads(pickle.dumps(error))
    except Exception:
        return RuntimeError(text.splitlines()[-1])
    return error


def _run_and_send(sender, function: Callable, jobs: dict[str, tuple], tie: Callable) -> None:
    """In the child: run each job and send ``(name, done, result or (error, traceback))``;
    ``tie`` first, so that the child ends with its parent, killed or not."""
    tie()
    for name, arguments in jobs.items():
        try:
            sent = (name, True, function(*arguments))
        except Exception as error:  # raised in the parent, where the result is asked for
            text = traceback.format_exc()
            sent = (name, False, (_portable(error, text), text))
        try:
            sender.send(sent)
        except Exception:  # a result or an error that does not pickle
            text = traceback.format_exc()
            sender.send((name, False, (RuntimeError(f"{name}: {text.splitlines()[-1]}"), text)))
    sender.close()
