"""Process hygiene: worker processes die with the run that started them; SIGTERM ends a run as Ctrl-C does.

A process pool's workers otherwise outlive a SIGKILLed parent (they block on their task queue,
whose pipe they hold both ends of), and with them the fork server and the resource tracker,
which wait for every client to go. :func:`exit_with` watches the parent from a daemon thread
(``pidfd`` on Linux, polling elsewhere) and ends the worker as soon as the parent is gone; the
fork server and the tracker then see end-of-file and exit by themselves.
"""
from __future__ import annotations

import atexit
import os
import select
import signal
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager, suppress

__all__ = ["exit_with", "Terminated", "handle_termination", "ignore_interrupts", "start_forkserver_ignoring_interrupts",
           "signal_received", "raise_if_signalled", "signals_held", "release_signals", "settle", "guard_exit",
           "stop_message"]


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
_RUN = [0]  # where the current run's signals start in _RECEIVED (handle_termination begins a run)
_HOLD = [0]  # depth of signals_held in the main thread: the handlers record instead of raising


def _stop(signum: int) -> KeyboardInterrupt:
    return KeyboardInterrupt() if signum == signal.SIGINT else Terminated(signum)


def _record_or_raise(signum, frame):
    _RECEIVED.append(signum)
    if not _HOLD[0]:
        raise _stop(signum)


_raise_terminated = _raise_interrupt = _record_or_raise  # (the names the handlers are known by)


def _unraisable(hook):
    def quiet_stop(args):
        if isinstance(args.exc_value, KeyboardInterrupt) and signal_received() is not None:
            # the handler's exception met a finaliser or a weakref callback ("Exception ignored in ...
            # _get_module_lock"), where Python drops it: the next checkpoint (raise_if_signalled) or
            # the CLI's end raises it instead; no traceback
            return
        hook(args)
    quiet_stop.swatch_quiet_stop = True  # type: ignore[attr-defined]
    return quiet_stop


@contextmanager
def signals_held() -> Iterator[None]:
    """Defer SIGINT/SIGTERM/SIGHUP over a block (moving staged files into place, starting a worker, the
    cleanup after a stop): a signal that comes meanwhile is raised when the block ends.

    The handlers themselves defer (a mask alone would not do: a process-wide signal goes to any thread
    that does not block it, the pool's manager thread for one, and Python then runs the handler in the
    main thread at once). Nested blocks raise at the outermost end; a stop already unwinding is left as
    it is, another exception gives way to the stop.

    Yields
    ------
    None
        With the signals deferred (raised when the block ends); outside the main thread, nothing deferred.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    start = len(_RECEIVED)
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM, signal.SIGHUP})
    _HOLD[0] += 1

    def release() -> int | None:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)  # (a signal the mask kept runs its handler here: recorded)
        _HOLD[0] -= 1
        return _RECEIVED[start] if not _HOLD[0] and len(_RECEIVED) > start else None

    try:
        yield
    except KeyboardInterrupt:
        release()
        raise
    except BaseException:
        if (sig := release()) is not None:
            raise _stop(sig) from None
        raise
    if (sig := release()) is not None:
        raise _stop(sig)


def release_signals(mask) -> None:
    """Put back the signal mask ``mask`` that a block of SIGINT/SIGTERM/SIGHUP replaced (the program's
    start, held from the first statement of ``swatch.cli`` until the handlers are in place): the signals
    that came meanwhile are all recorded, and the first is raised, once (unmasked with the handlers
    raising, a second one, SIGHUP and SIGTERM from a closed terminal, was raised again while the first
    was being reported: a traceback).

    Parameters
    ----------
    mask : set of int
        What ``signal.pthread_sigmask`` returned when the block began.

    Raises
    ------
    KeyboardInterrupt
        After a SIGINT held meanwhile.
    Terminated
        After a SIGTERM or SIGHUP held meanwhile.
    """
    start = len(_RECEIVED)
    _HOLD[0] += 1
    try:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # (the held signals run their handlers here: recorded)
    finally:
        _HOLD[0] -= 1
    if not _HOLD[0] and len(_RECEIVED) > start:
        raise _stop(_RECEIVED[start])


def signal_received() -> int | None:
    """The first termination signal the current run received (since :func:`handle_termination`), or None:
    an error raised while a run is being stopped (a worker gone, a pool broken) is reported as the stop,
    not as a failure.

    Returns
    -------
    int or None
        The signal number.
    """
    return _RECEIVED[_RUN[0]] if len(_RECEIVED) > _RUN[0] else None


def raise_if_signalled() -> None:
    """Raise the stop a signal asked for if it has not been raised yet, or was lost on the way: the
    exception raised while C++ runs Python code (Mitsuba calling the film BSDF plugin while it loads or
    traces a scene) is swallowed there, and the render ran on to the end, exit 0 (a SIGTERM at 9 s); one
    raised in a finaliser or weakref callback is dropped by Python (a rebuild finished, exit 0). Called
    between the pieces of long work.

    Raises
    ------
    KeyboardInterrupt
        After a SIGINT.
    Terminated
        After a SIGTERM or SIGHUP.
    """
    sig = signal_received()
    if sig is not None:
        raise _stop(sig)


def stop_message(signum: int) -> tuple[str, int]:
    """The one line and the exit status of a run stopped by a signal.

    Parameters
    ----------
    signum : int
        The signal.

    Returns
    -------
    (str, int)
        ``error: interrupted; …`` (SIGINT) or ``error: terminated; …``, and 130 or 128 + the signal.
    """
    what = "interrupted" if signum == signal.SIGINT else "terminated"
    return f"error: {what}; nothing half-written was left behind", 128 + signum


_SETTLED: list[int] = []  # [exit status, signals received by then] once the program's outcome is settled


def settle(status: int) -> None:
    """The program's outcome is ``status``: from now on (its exit: atexit, the pool's and the tracker's
    finalisers, Python's own finalisation) a termination signal is recorded, not raised; one that comes
    before the process is gone still ends a successful run with its one line and 130/143, from the exit
    handler of :func:`guard_exit` (it killed the process raw once Python had restored the default
    handlers, or printed a traceback from an atexit callback). For the program only (``swatch`` itself),
    never in a process that goes on.

    Called again (the CLI settles as soon as its run is over, then once more if a stop lost on its way turned
    a success into 130), it settles on the new status; the signals up to then count as seen.

    Parameters
    ----------
    status : int
        The exit status the run settled on.

    Returns
    -------
    None
    """
    if threading.current_thread() is not threading.main_thread():
        return
    if not _SETTLED:
        _HOLD[0] += 1  # (for good: the handlers record from here on)
    _SETTLED[:] = [status, len(_RECEIVED)]


def guard_exit() -> None:
    """At a program's start: its last exit handler (registered before any other of the run's: atexit calls
    them in reverse) reports a signal that came after :func:`settle` (one line, 130/143) and ends the
    process there with the settled status (what is left, Python tearing its modules down, is where a
    signal was lost or killed the process raw).

    Returns
    -------
    None
    """
    atexit.register(_late_stop)


def _late_stop() -> None:
    if not _SETTLED:
        return
    status, seen = _SETTLED
    for stream in (sys.stdout, sys.stderr):
        with suppress(OSError, ValueError):
            stream.flush()
    late = _RECEIVED[seen:]
    if late and status == 0:
        line, status = stop_message(late[0])
        os.write(2, (line + "\n").encode())
    # the last exit handler: the process ends here, with the settled status. Past this point Python tears its
    # modules down (a tenth of a second and more with numpy, colour-science and OpenImageIO loaded), then puts
    # the default handlers back: a signal then was lost (SIG_IGN; a rebuild signalled at its end exited 0) or
    # killed the process raw (no line)
    os._exit(status)


def handle_termination() -> None:
    """SIGTERM and SIGHUP raise :class:`Terminated` (a KeyboardInterrupt) in the main thread; a run begins
    (:func:`signal_received` counts its signals only), and a stop that a finaliser or weakref callback
    dropped prints nothing (``sys.unraisablehook``): :func:`raise_if_signalled` raises it again.

    Returns
    -------
    None
        (Installs the handlers; nothing outside the main thread.)
    """
    if threading.current_thread() is not threading.main_thread():
        return
    _RUN[0] = len(_RECEIVED)  # (a new run: signals before it were an earlier run's, in a process that goes on)
    for sig in (signal.SIGTERM, signal.SIGHUP):
        if signal.getsignal(sig) in (signal.SIG_DFL, None):
            signal.signal(sig, _raise_terminated)
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, _raise_interrupt)  # (as Python's own, and remembered)
    if not getattr(sys.unraisablehook, "swatch_quiet_stop", False):
        sys.unraisablehook = _unraisable(sys.unraisablehook)
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
    instead lost a Ctrl-C sent in that second: the build went on and exited 0); the handlers record
    meanwhile (the kernel may give the signal to another thread, and Python ran the handler in this one
    at once, in the middle of the start), and the first signal is raised once the server is up. A server
    already running is left as it is.

    Returns
    -------
    None
    """
    from multiprocessing import forkserver, resource_tracker  # stdlib, 0.2 s: kept off every command's start

    if threading.current_thread() is not threading.main_thread():
        forkserver.ensure_running()
        return
    held = {signal.SIGINT, signal.SIGHUP}
    start = len(_RECEIVED)
    _HOLD[0] += 1
    old = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        # the tracker first: it ignores SIGINT and SIGTERM itself, inherits SIGHUP held, and unblocks
        # SIGINT and SIGTERM here when it has started (a Ctrl-C then is recorded, and raised below)
        resource_tracker.ensure_running()
        signal.pthread_sigmask(signal.SIG_BLOCK, held)
        forkserver.ensure_running()
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)  # (a signal held meanwhile is recorded here)
        _HOLD[0] -= 1
    if not _HOLD[0] and len(_RECEIVED) > start:
        raise _stop(_RECEIVED[start])


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
