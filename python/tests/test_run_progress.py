"""salsa.run's progress: the program's lines passed on as it prints them, its live bar in a terminal,
nothing with quiet=True."""

import os
import pty
import subprocess
import sys
import time

import salsa
from conftest import SMALL, SOURCE

# A second or more of stepping: 300 drones for 20 s.
LONG = {**SMALL, "name": "long", "drones": 300, "time": 20, "seed": 3}


class Recorder:
    """A sys.stdout that notes, at each write, whether the long test had finished then."""

    def __init__(self, out):
        self.out, self.writes = out, []

    def write(self, text):
        self.writes.append((text, (self.out / "long" / "config.json").exists()))
        return len(text)

    def flush(self):
        pass


def with_stdout(stream, call):
    saved, sys.stdout = sys.stdout, stream
    try:
        return call()
    finally:
        sys.stdout = saved


def test_lines_come_as_tests_finish(tmp_path):
    out = tmp_path / "out"
    recorder = Recorder(out)
    with_stdout(recorder, lambda: salsa.run([{**SMALL, "time": 1}, LONG], out=out, jobs=1, plots=False, quiet=False))
    text = "".join(t for t, _ in recorder.writes)
    assert text.startswith("[1/2] small: 1.00 s simulated") and "[2/2] long: 20.00 s simulated" in text
    assert text.endswith(f"results in {out}\n")
    # The first test's line was passed on while the second still ran, not when the program ended.
    assert recorder.writes[0][0].startswith("[1/2] small") and not recorder.writes[0][1]


def test_quiet_prints_nothing(tmp_path):
    recorder = Recorder(tmp_path)
    with_stdout(recorder, lambda: salsa.run(SMALL, out=tmp_path / "a", plots=False, time=1))
    assert recorder.writes == []
    # Nor does the program write to the process's own output.
    code = f"import salsa; salsa.run({SMALL!r}, out={str(tmp_path / 'b')!r}, plots=False, time=1)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=SOURCE)
    assert done.returncode == 0, done.stderr
    assert done.stdout == "" and done.stderr == ""


def run_in_a_terminal(code):
    """What a python running `code` with a terminal as its stdout shows, with when each piece came."""
    leader, follower = pty.openpty()
    process = subprocess.Popen([sys.executable, "-c", code], stdout=follower, stderr=subprocess.PIPE, cwd=SOURCE)
    os.close(follower)
    pieces = []
    while True:
        try:
            chunk = os.read(leader, 4096)
        except OSError:
            break
        if not chunk:
            break
        pieces.append((time.monotonic(), chunk.decode()))
    os.close(leader)
    assert process.wait() == 0, process.stderr.read()
    process.stderr.close()
    return pieces


def test_a_terminal_gets_the_live_bar(tmp_path):
    for quiet in (False, True):
        code = f"import salsa; salsa.run({LONG!r}, out={str(tmp_path / str(quiet))!r}, plots=False, quiet={quiet})"
        pieces = run_in_a_terminal(code)
        text = "".join(p for _, p in pieces)
        if quiet:
            assert text == ""
            continue
        # The bar, redrawn in place while the test runs (every 250 ms), then the folder.
        bars = [(t, p) for t, p in pieces if "\r\x1b[K[" in p and " tests" in p]
        assert len(bars) >= 2, text
        assert "0/1 tests, 1 running" in text and "sim s/s, ETA" in text
        assert text.rstrip().endswith(f"results in {tmp_path / str(quiet)}")
        assert pieces[-1][0] - bars[0][0] > 0.2  # the first bar came well before the end
