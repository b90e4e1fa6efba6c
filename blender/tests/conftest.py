"""The add-on's tests run in a Python that has `bpy` (Blender as a module,
pip install bpy==4.5.15) and Tyndall's wheel; they are skipped, with a
message, where bpy cannot be imported."""

import os
import sys

import pytest

try:
    import bpy  # noqa: F401

    HAVE_BPY = True
except ImportError:
    HAVE_BPY = False


def pytest_collection_modifyitems(config, items):
    if HAVE_BPY:
        return
    skip = pytest.mark.skip(reason="bpy is not installed in this Python (pip install bpy==4.5.15): add-on tests skipped")
    for item in items:
        item.add_marker(skip)


def pytest_unconfigure(config):
    # bpy 4.5's module hangs at interpreter exit after a few renders that
    # write and read image files: the main thread waits forever in the
    # destructor of its delayed-file-close thread's state
    # (GlobalState::~GlobalState, seen with gdb). Leave at once instead,
    # with pytest's exit status, once pytest has reported.
    if HAVE_BPY:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(int(getattr(config, "_tyndall_exit_status", 0)))


def pytest_sessionfinish(session, exitstatus):
    session.config._tyndall_exit_status = int(exitstatus)
