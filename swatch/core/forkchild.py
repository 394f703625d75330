"""Imported first in multiprocessing's fork server (the catalog pool's preload list), nowhere else:
a worker the server forks after the build that asked for it has gone (stopped by Ctrl-C, SIGTERM,
SIGHUP while the server was still importing) fails to unpickle its start-up data (the build's
semaphores are gone with it) and printed that traceback into the user's terminal, after the build's
one line. The server's children report an uncaught exception only while the build is alive.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

__all__ = ["BUILD_PID", "build_alive"]

#: The process that started the fork server (the build): the server is its child.
BUILD_PID = os.getppid()
_default_hook = sys.excepthook


def build_alive() -> bool:
    """Whether the build process is still running (not gone, not a zombie waiting to be reaped).

    Returns
    -------
    bool
        True while ``BUILD_PID`` exists and is not a zombie (also when it cannot be examined); False otherwise.
    """
    try:
        os.kill(BUILD_PID, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        stat = Path(f"/proc/{BUILD_PID}/stat").read_text()
    except OSError:
        return True  # (no /proc: alive as far as kill says)
    return stat[stat.rindex(")") + 2:][:1] not in ("Z", "X")


def _quiet_once_the_build_is_gone(kind, value, tb) -> None:
    if build_alive():
        _default_hook(kind, value, tb)


sys.excepthook = _quiet_once_the_build_is_gone
