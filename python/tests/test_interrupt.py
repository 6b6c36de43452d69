"""Ctrl-C during a long render: KeyboardInterrupt within a fraction of a second at any phase
(the image buffers' set-up, the tiles, the outline, the copy out), measured from the SIGINT sent
by a timer thread to the moment the exception arrives. The bound, 2 s, leaves room for a machine
loaded by the rest of the suite; a render that does not check for signals takes 10-60 s."""

import os
import signal
import threading
import time

import pytest

import cover


def interrupt_latency(call, delay):
    """Seconds from a SIGINT sent `delay` s after `call` starts to its KeyboardInterrupt, or None
    when the call ended first."""
    sent = []

    def fire():
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(delay, fire)
    timer.start()
    try:
        call()
    except KeyboardInterrupt:
        return time.monotonic() - sent[0]
    finally:
        timer.cancel()
    try:  # the call ended first: take the signal here
        time.sleep(1)
    except KeyboardInterrupt:
        pass
    return None


def test_ctrl_c_stops_a_large_render_within_two_seconds(bunny_path):
    m = cover.load(bunny_path)
    m.render(64, 64)
    # 6000²: 250 MB of image buffers whose first touch (page faults) took seconds without a
    # check for signals; then the tiles, the outline and the copy out.
    latencies = [interrupt_latency(lambda: m.render(6000, 6000, threads=2), d)
                 for d in (0.02, 0.3, 1.0)]
    measured = [t for t in latencies if t is not None]
    assert measured, "every render ended before its interrupt"
    assert max(measured) < 2, latencies
