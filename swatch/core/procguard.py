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

__all__ = ["exit_with", "Terminated", "handle_termination", "ignore_interrupts", "start_forkserver_ignoring_interrupts",
           "signal_received", "raise_if_signalled"]


class Terminated(KeyboardInterrupt):
    """Raised in the main thread on SIGTERM/SIGHUP, so cleanup runs exactly as for Ctrl-C.

    Parameters
    ----------
    signum : int
        The signal (``signal.SIGTERM`` or ``signal.SIGHUP``); the CLI exits with 128 + it.
    """

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


_RECEIVED: list[int] = []  # the termination signals this process got (SIGINT, SIGTERM, SIGHUP)


def _raise_terminated(signum, frame):
    _RECEIVED.append(signum)
    raise Terminated(signum)


def _raise_interrupt(signum, frame):
    _RECEIVED.append(signum)
    raise KeyboardInterrupt


def signal_received() -> int | None:
    """The first termination signal this process received, or None: an error raised while a run is
    being stopped (a worker gone, a pool broken) is reported as the stop, not as a failure.

    Returns
    -------
    int or None
        The signal number.
    """
    return _RECEIVED[0] if _RECEIVED else None


def raise_if_signalled() -> None:
    """Raise the stop a signal asked for if it has not been raised yet, or was lost on the way: the
    exception raised while C++ runs Python code (Mitsuba calling the film BSDF plugin while it loads or
    traces a scene) is swallowed there, and the render ran on to the end, exit 0 (a SIGTERM at 9 s).
    Called between the pieces of long native work.

    Raises
    ------
    KeyboardInterrupt
        After a SIGINT.
    Terminated
        After a SIGTERM or SIGHUP.
    """
    sig = signal_received()
    if sig is None:
        return
    if sig == signal.SIGINT:
        raise KeyboardInterrupt
    raise Terminated(sig)


def handle_termination() -> None:
    """SIGTERM and SIGHUP raise :class:`Terminated` (a KeyboardInterrupt) in the main thread.

    Returns
    -------
    None
        (Installs the handlers; nothing outside the main thread.)
    """
    if threading.current_thread() is not threading.main_thread():
        return
    for sig in (signal.SIGTERM, signal.SIGHUP):
        if signal.getsignal(sig) in (signal.SIG_DFL, None):
            signal.signal(sig, _raise_terminated)
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, _raise_interrupt)  # (as Python's own, and remembered)
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        if signal.getsignal(sig) in (_raise_interrupt, _raise_terminated):
            # SA_RESTART: a write of libpng or OpenEXR that the signal meets is resumed, not failed with
            # EINTR (a "libpng error: Write Error" line after the run's own); Python still raises the
            # exception as soon as the C call returns (waits on locks, sleeps and selects are cut short)
            signal.siginterrupt(sig, False)


def ignore_interrupts() -> None:
    """For workers: Ctrl-C and a hang-up go to the whole process group; only the parent reacts (one
    message, no worker traceback). SIGTERM keeps its default (the pool ends broken workers with it).

    Returns
    -------
    None
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGHUP, signal.SIG_IGN)


def start_forkserver_ignoring_interrupts() -> None:
    """Start multiprocessing's fork server (and the resource tracker) with SIGINT and SIGHUP blocked,
    so that neither they nor any worker forked from the server reacts to a Ctrl-C or a hang-up sent
    to the process group, from its first instruction (not only once its initializer has run).

    The blocked mask survives the server's exec and every fork (the server then ignores SIGINT
    itself; a worker's initializer ignores both). In this process the signals are only held, not
    ignored: one that arrives meanwhile is delivered when the server is up (setting SIG_IGN here
    instead lost a Ctrl-C sent in that second: the build went on and exited 0). A server already
    running is left as it is.

    Returns
    -------
    None
    """
    from multiprocessing import forkserver, resource_tracker  # stdlib, 0.2 s: kept off every command's start

    if threading.current_thread() is not threading.main_thread():
        forkserver.ensure_running()
        return
    held = {signal.SIGINT, signal.SIGHUP}
    old = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        # the tracker first: it ignores SIGINT and SIGTERM itself, inherits SIGHUP held, and unblocks
        # SIGINT and SIGTERM here when it has started (a Ctrl-C then is this process's, as it should be)
        resource_tracker.ensure_running()
        signal.pthread_sigmask(signal.SIG_BLOCK, held)
        forkserver.ensure_running()
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)  # (a signal held meanwhile is raised here)


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
    """End this process (immediately, ``os._exit``) when process ``pid`` ends (a watcher thread).

    Parameters
    ----------
    pid : int
        The process to follow (the build, for a pool worker).
    """
    try:
        fd = os.pidfd_open(pid)
    except ProcessLookupError:
        os._exit(1)  # already gone
    except (AttributeError, OSError):
        threading.Thread(target=_watch_poll, args=(pid,), daemon=True, name="exit-with-parent").start()
        return
    threading.Thread(target=_watch_pidfd, args=(fd,), daemon=True, name="exit-with-parent").start()
