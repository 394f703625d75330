"""Process hygiene: worker processes die with the run that started them; SIGTERM ends a run as Ctrl-C does.

A process pool's workers otherwise outlive a SIGKILLed parent (they block on their task queue,
whose pipe they hold both ends of), and with them the fork server and the resource tracker,
which wait for every client to go. :func:`exit_with` watches the parent from a daemon thread
(``pidfd`` on Linux, polling elsewhere) and ends the worker as soon as the parent is gone; the
fork server and the tracker then see end-of-file and exit by themselves.
"""
from __future__ import annotations

import os
import select
import signal
import threading
import time
from multiprocessing import forkserver

__all__ = ["exit_with", "Terminated", "handle_termination", "ignore_interrupts", "start_forkserver_ignoring_interrupts"]


class Terminated(KeyboardInterrupt):
    """Raised in the main thread on SIGTERM/SIGHUP, so cleanup runs exactly as for Ctrl-C."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


def _raise_terminated(signum, frame):
    raise Terminated(signum)


def handle_termination() -> None:
    """SIGTERM and SIGHUP raise :class:`Terminated` (a KeyboardInterrupt) in the main thread."""
    if threading.current_thread() is not threading.main_thread():
        return
    for sig in (signal.SIGTERM, signal.SIGHUP):
        if signal.getsignal(sig) in (signal.SIG_DFL, None):
            signal.signal(sig, _raise_terminated)


def ignore_interrupts() -> None:
    """For workers: Ctrl-C goes to the whole process group; only the parent reacts (one message)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def start_forkserver_ignoring_interrupts() -> None:
    """Start multiprocessing's fork server with SIGINT ignored, so every worker forked from it ignores
    Ctrl-C from its first instruction (not only once its initializer has run).

    The disposition SIG_IGN survives the server's exec, and the server restores it in each child.
    A server already running is left as it is.
    """

    if threading.current_thread() is not threading.main_thread():
        forkserver.ensure_running()
        return
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        forkserver.ensure_running()
    finally:
        signal.signal(signal.SIGINT, old)


def _watch_pidfd(fd: int) -> None:
    select.select([fd], [], [])  # readable once the process has exited
    os._exit(1)


def _watch_poll(pid: int) -> None:
    while True:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            os._exit(1)
        except PermissionError:
            pass
        time.sleep(0.5)


def exit_with(pid: int) -> None:
    """End this process (immediately, ``os._exit``) when process ``pid`` ends."""
    try:
        fd = os.pidfd_open(pid)
    except ProcessLookupError:
        os._exit(1)  # already gone
    except (AttributeError, OSError):
        threading.Thread(target=_watch_poll, args=(pid,), daemon=True, name="exit-with-parent").start()
        return
    threading.Thread(target=_watch_pidfd, args=(fd,), daemon=True, name="exit-with-parent").start()
