"""Ctrl-C (SIGINT) stops a long run promptly and keeps what was recorded."""

import os
import signal
import threading
import time

import pytest

import curvenet


@pytest.fixture(autouse=True)
def keyboard_interrupt_on_sigint():
    """Ctrl-C raises KeyboardInterrupt even when the test process started with SIGINT
    ignored (a shell's background job does: Python then keeps the signal ignored)."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_keyboard_interrupt_stops_the_greedy_promptly(tmp_path):
    net = curvenet.example("tower")
    sent = {}

    def interrupt():
        sent["at"] = time.monotonic()
        os.kill(os.getpid(), signal.SIGINT)

    started = []

    def progress(it):
        if not started:
            started.append(it)
            threading.Timer(0.5, interrupt).start()

    with pytest.raises(KeyboardInterrupt):
        net.simplify(out=tmp_path / "run", pictures=False, progress=progress)
    stopped = time.monotonic() - sent["at"]
    # Stops within about a second (candidate scoring polls between candidates); the bound is
    # loose for a loaded machine.
    assert stopped < 5.0, stopped
    partial = curvenet.open_run(tmp_path / "run")
    assert not partial.complete and len(partial.iterations) >= 1


@pytest.fixture(scope="module")
def demo_sketch(cli, tmp_path_factory):
    """The demo's sketch: 24 random geodesics on the built-in dome (the command line's
    interrupt tests use it too: its steps after the greedy take seconds)."""
    d = tmp_path_factory.mktemp("sketch")
    cli("trace", "--mesh", "dome", "--geodesics", "24", "--seed", "1", "--out", d / "c.json")
    return curvenet.load([d / "c.json"], mesh="dome", edge_length=100)


@pytest.mark.parametrize("stage,kw", [
    ("local search", {"local_search": True}),
    ("alternatives", {"alternatives": 3}),
    ("certificate", {"certify": True}),
])
def test_keyboard_interrupt_stops_the_steps_after_the_greedy(demo_sketch, tmp_path, stage, kw):
    sent = {}

    def interrupt():
        sent["at"] = time.monotonic()
        os.kill(os.getpid(), signal.SIGINT)

    def progress(it):
        # The greedy's last iteration (nothing removed next): the step after it starts now.
        if it.removed is None:
            threading.Timer(0.3, interrupt).start()

    with pytest.raises(KeyboardInterrupt):
        demo_sketch.simplify(0.3, out=tmp_path / "run", pictures=False, progress=progress, **kw)
    stopped = time.monotonic() - sent["at"]
    assert stopped < 2.0, (stage, stopped)
    # The greedy's iterations are kept for a resume.
    partial = curvenet.open_run(tmp_path / "run")
    assert not partial.complete and partial.iterations[-1].removed is None
