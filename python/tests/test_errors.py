"""A Python library's manners: bad arguments raise ValueError/TypeError with
the CLI's message, files raise OSError, a memory refusal raises
MemoryLimitError with its estimate; nothing crashes the interpreter; Ctrl-C
stops a long run; the GIL is released while the engine works."""

import os
import re
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import asperity

PTS = np.random.default_rng(0).normal(size=(50, 3))
CUBE = asperity.Mesh(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    [[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5],
     [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])

CASES = [
    (ValueError, lambda: asperity.rd(size=0)),
    (ValueError, lambda: asperity.rd(dim=3)),
    (ValueError, lambda: asperity.rd(layers=-1)),
    (ValueError, lambda: asperity.rd(runs=0)),
    (ValueError, lambda: asperity.rd(size=32, bin=7)),
    (ValueError, lambda: asperity.rdsr(fit_window=(5, 1))),
    (ValueError, lambda: asperity.bd(substrate="cone")),
    (ValueError, lambda: asperity.bd(substrate="mesh")),
    (TypeError, lambda: asperity.rd(size="big")),
    (ValueError, lambda: asperity.dla(seed_shape="blob")),
    (ValueError, lambda: asperity.dla(stick=0)),
    (ValueError, lambda: asperity.dla(dim=4)),
    (ValueError, lambda: asperity.dla(size=(1, 2))),
    (ValueError, lambda: asperity.dla(particles=0)),
    (ValueError, lambda: asperity.reconstruct(np.zeros((0, 3)))),
    (ValueError, lambda: asperity.reconstruct(np.zeros((5, 2)))),
    (ValueError, lambda: asperity.reconstruct(PTS, flow="wavy")),
    (TypeError, lambda: asperity.reconstruct(PTS, flux=1)),
    (ValueError, lambda: asperity.ca_run(10**12, 10)),
    (ValueError, lambda: asperity.ca_run(450, 10, family="hex")),
    (ValueError, lambda: asperity.ca_run(450, 10, init="bogus")),
    (ValueError, lambda: asperity.ifs_surface("no-such-preset")),
    (ValueError, lambda: asperity.ifs_curve("bezier-bicubic")),
    (ValueError, lambda: asperity.ifs_dcf("bezier-cubic", operator=2)),
    (ValueError, lambda: asperity.surface_ca("builtin:torus")),
    (ValueError, lambda: asperity.surface_ca(CUBE, app="life")),
    (TypeError, lambda: asperity.surface_ca(CUBE, colour=3)),
    (ValueError, lambda: asperity.subdiv(detail=["lava"])),
    (OSError, lambda: asperity.subdiv("levels = 2\nbase = 'nothing-here.ply'\n")),
    (ValueError, lambda: asperity.fbm(size=0)),
    (ValueError, lambda: asperity.fbm(hurst=1.5)),
    (OSError, lambda: asperity.load("/nonexistent/file.ply")),
    (OSError, lambda: CUBE.save("/nonexistent-dir/x.ply")),
    (ValueError, lambda: CUBE.save("/tmp/x.unknownext")),
    (TypeError, lambda: asperity.analyze("not a surface")),
    (ValueError, lambda: asperity.analyze(asperity.Mesh(CUBE.vertices, [[0, 1, 99]]))),
    (ValueError, lambda: asperity.render(CUBE, view="diagonal")),
    (ValueError, lambda: asperity.render(CUBE, shader="toon")),
    (ValueError, lambda: asperity.rd(size=16, layers=2, threads=0)),
    (ValueError, lambda: asperity.Mesh(np.zeros((3, 2)), [[0, 1, 2]])),
    (ValueError, lambda: asperity.HeightField(np.zeros(5))),
]


@pytest.mark.parametrize("expected,call", CASES, ids=[f"case{i}" for i in range(len(CASES))])
def test_bad_arguments_raise(expected, call):
    with pytest.raises(expected) as e:
        call()
    assert str(e.value), "the exception says why"


@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf"), np.float64("nan")])
def test_a_number_that_is_not_finite_is_refused_naming_it(value):
    """NaN and ±inf reach no job (an optional one would read as unset in JSON)."""
    with pytest.raises(ValueError, match="rms must be a finite number"):
        asperity.fbm(size=16, rms=value)
    with pytest.raises(ValueError, match="tolerance must be a finite number"):
        asperity.reconstruct(PTS, tolerance=value)


def test_at_least_twenty_cases():
    assert len(CASES) >= 20


@pytest.mark.parametrize("py_call,cli_args", [
    (lambda: asperity.rdsr(fit_window=(5, 1)), ["growth", "rdsr", "--fit-window", "5,1", "-o", "x.npy"]),
    (lambda: asperity.dla(stick=0), ["growth", "dla", "--stick", "0", "-o", "x.ply"]),
    (lambda: asperity.rd(size=32, bin=7), ["growth", "rd", "--size", "32", "--bin", "7", "-o", "x.npy"]),
    (lambda: asperity.fbm(hurst=1.5), ["generate", "fbm", "--hurst", "1.5", "-o", "x.npy"]),
    (lambda: asperity.ifs_surface("no-such-preset"), ["ifs", "surface", "--preset", "no-such-preset", "-o", "x.ply"]),
    (lambda: asperity.ca_run(450, 10, init="bogus"), ["ca", "run", "--rule", "450", "--steps", "10", "--init", "bogus", "-o", "x.npy"]),
])
def test_messages_are_the_clis(cli, tmp, py_call, cli_args):
    with pytest.raises(ValueError) as e:
        py_call()
    p = cli(*[tmp / a if a.startswith("x.") else a for a in cli_args], json_report=False, check=False)
    assert p.returncode != 0
    first = p.stderr.strip().splitlines()[0]
    # the same message, each naming the parameter its own way: --fit-window / fit_window=
    assert "--" not in str(e.value)
    assert first == f"error: {re.sub(r'([a-z_0-9]+)=', lambda m: '--' + m[1].replace('_', '-'), str(e.value))}"


def test_memory_refusal_has_its_estimate():
    asperity.set_limits(max_memory=1 << 20)
    try:
        with pytest.raises(asperity.MemoryLimitError) as e:
            asperity.fbm(size=4096)
        assert isinstance(e.value, MemoryError)
        assert e.value.needed > e.value.limit == 1 << 20
        assert "MiB" in str(e.value)
        assert "raise it with max_memory=" in str(e.value), "a keyword, not the CLI's flag"
    finally:
        asperity.set_limits()
    assert asperity.fbm(size=16).heights.shape == (16, 16)


def test_memory_budget_says_where_it_came_from(cli, tmp):
    """The budget a job runs under, as the CLI's --json report gives it: the
    system's by default (the same from both), "given" after set_limits."""
    system = asperity.memory_budget()
    assert system["from"] in {"half_of_ram", "cgroup", "rlimit_as", "rlimit_data"}
    report = cli("generate", "fbm", "--size", 8, "-o", tmp / "f.npy")
    assert report["memory_budget"]["from"] == system["from"]
    assert abs(report["memory_budget"]["bytes"] - system["bytes"]) <= max(system["bytes"] // 10, 1 << 20)
    asperity.set_limits(max_memory=3 << 20)
    try:
        assert asperity.memory_budget() == {"bytes": 3 << 20, "from": "given"}
    finally:
        asperity.set_limits()
    assert asperity.memory_budget()["from"] == system["from"]


def test_time_refusal():
    with pytest.raises(asperity.TimeLimitError):
        asperity.ca_run(450, 10**9, size=(4096, 4096), init="random:0.5")


def _task_count():
    return len(os.listdir("/proc/self/task"))


def test_keyboard_interrupt_stops_a_long_run():
    # Ctrl-C as an interactive Python has it: a suite started in the
    # background of a non-interactive shell inherits SIGINT ignored, and
    # Python keeps it ignored (the run then went on for minutes). A run that
    # hangs anyway dumps its stacks and exits; lines are flushed as they come.
    # Bounded by work, not seconds (a busy machine stretches every delay): the
    # run of 10^7 particles stops with a tenth of them done at most, and its
    # worker thread ends. The delay is printed; the engine stops at its next
    # progress report, polled every 0.1 s.
    script = textwrap.dedent("""
        import faulthandler, functools, os, signal, threading, time, asperity
        signal.signal(signal.SIGINT, signal.default_int_handler)
        faulthandler.dump_traceback_later(90, exit=True)
        print = functools.partial(print, flush=True)
        def tasks(): return len(os.listdir('/proc/self/task'))
        before = tasks()
        seen = [0, 1]
        def progress(done, total, message): seen[:] = [done, max(total, 1)]
        threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
        t0 = time.time()
        try:
            asperity.dla(particles=10**7, threads=2, progress=progress)   # minutes of work
            print('NOT INTERRUPTED')
        except KeyboardInterrupt:
            print('interrupted after', round(time.time() - t0 - 1.0, 3), 's, done', seen[0] / seen[1])
        while tasks() > before:
            time.sleep(0.05)
        print('threads left', tasks() - before)
        print('still works', asperity.fbm(size=16).heights.shape)
    """)
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    out = p.stdout
    print(out)
    assert p.returncode == 0, out + p.stderr
    assert "interrupted after" in out, out
    done = float(out.split("done")[1].split()[0])
    assert done < 0.1, out
    assert "threads left 0" in out, out  # the worker thread stopped, not abandoned
    assert "still works (16, 16)" in out


def test_a_running_call_lets_other_threads_run():
    # With the GIL released, Python code on another thread keeps running for
    # the whole call; with it held, that thread stands still from the call's
    # start to its end. Counted in the other thread's steps in each half of
    # the call, not in seconds (which a loaded machine may stretch).
    kw = dict(size=256, layers=1500, threads=1)
    asperity.rd(size=16, layers=2)
    span = {}

    def work():
        span["start"] = time.perf_counter()
        asperity.rd(**kw)
        span["end"] = time.perf_counter()

    worker = threading.Thread(target=work)
    stamps = []
    worker.start()
    while worker.is_alive():
        stamps.append(time.perf_counter())
    worker.join()
    start, end = span["start"], span["end"]
    middle = 0.5 * (start + end)
    halves = [sum(start < t < middle for t in stamps), sum(middle <= t < end for t in stamps)]
    assert min(halves) >= 100, (
        f"another thread ran {halves} steps in the halves of a {end - start:.3f}s call: the GIL is held")


def test_progress_callback_is_called():
    seen = []
    asperity.dla(particles=30_000, progress=lambda d, t, m: seen.append((d, t, m)))
    assert seen, "progress was reported"
    assert all(t >= d for d, t, _ in seen if t)


def test_progress_bar_with_tqdm(capsys):
    r = asperity.dla(particles=30_000, progress=True)
    assert len(r.points) > 30_000
    err = capsys.readouterr().err
    assert "100%" in err or "it/s" in err, err[-300:]
    with pytest.raises(TypeError):
        asperity.dla(particles=10, progress="yes")
