"""Messages for the user, collected during a sync and shown once."""
import os
import traceback
from contextlib import contextmanager

from .. import native
from .camera import CameraError


class Reports:
    """Warnings and errors of one sync or render, each message kept once, in the order first seen."""

    def __init__(self):
        self._messages = {}  # message -> level ('WARNING' or 'ERROR'); a dict keeps first-seen order

    def warn(self, message):
        self._messages.setdefault(message, "WARNING")

    def error(self, message):
        self._messages[message] = "ERROR"

    def __bool__(self):
        return bool(self._messages)

    def __iter__(self):
        """(level, message) pairs."""
        return ((level, message) for message, level in self._messages.items())

    def emit(self, report, already_shown=None, warnings=True):
        """Pass each message to `report(level_set, message)` (RenderEngine.report). Messages in `already_shown`
        (a set, updated here) are skipped, so a viewport that syncs often does not repeat itself; warnings=False
        passes errors only."""
        for level, message in self:
            if level == "WARNING" and not warnings:
                continue
            if already_shown is not None:
                if message in already_shown:
                    continue
                already_shown.add(message)
            report({level}, message)


@contextmanager
def failures_reported(reports, what="Bounce"):
    """The engine boundary: an exception inside becomes an error report, never a traceback in front of the user.
    The traceback is printed only when the environment variable BOUNCE_DEBUG is set."""
    try:
        yield
    except (native.BounceError, CameraError) as error:
        reports.error(f"Bounce: {error}")
    except Exception as error:
        reports.error(f"{what} failed: {type(error).__name__}: {error}")
        if os.environ.get("BOUNCE_DEBUG"):
            traceback.print_exc()
