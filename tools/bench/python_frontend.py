"""What the Python front end costs beyond the analyses (issue 37's figures). Prints, does not judge:

  PYTHONPATH=build/python python3 tools/bench/python_frontend.py

1. a call around an analysis: flexmb.static on a model with nothing to solve, against the same
   call's analysis alone (the command line's `static` time is not comparable: it starts a process);
2. a Python USERSIG per right-hand side: the run with a callable that returns preset arrays, minus
   the run without it, minus the callable's own cost (timed by calling it directly), per call;
3. reading results: a result array handed out again and again, against copying it.
"""

import concurrent.futures
import os
import sys
import time

import numpy as np

import flexmb

SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def best(f, repeat=7, number=1):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            f()
        times.append((time.perf_counter() - t0) / number)
    return min(times)


def call_overhead():
    # One fixed bar: no degrees of freedom, no load steps to solve.
    m = flexmb.parse("PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nFIX 2\nEND\nEND\n", "noop.dat")
    t = best(lambda: flexmb.static(m, nev=0), number=2000)
    print(f"call around an analysis: flexmb.static on a model without degrees of freedom {t * 1e6:.2f} us per call")


def usersig_overhead():
    text = open(os.path.join(SRC, "tools", "octave", "tests", "data", "arm_expr.dat")).read()
    lines = [ln for ln in text.splitlines() if not ln.startswith(("XFT", "ESIGT"))]
    m = flexmb.parse("\n".join(lines) + "\n", "arm.dat")
    sig, f = np.zeros(m.ne), np.zeros(m.nx)
    calls = [0]

    def usersig(t, x, xd, e, ed):
        calls[0] += 1
        return sig, f

    plain = best(lambda: flexmb.simulate(m, t_end=1.0), repeat=5)
    with_user = best(lambda: flexmb.simulate(m, t_end=1.0, usersig=usersig), repeat=5)
    calls[0] = 0
    r = flexmb.simulate(m, t_end=1.0, usersig=usersig)
    n = calls[0]
    x = r.x[0]
    own = best(lambda: [usersig(0.0, x, x, x, x) for _ in range(n)], repeat=5) / n
    per_call = (with_user - plain) / n - own
    print(f"Python USERSIG: {n} calls in a run ({r.nfevals} right-hand sides), run {plain * 1e3:.2f} ms without, "
          f"{with_user * 1e3:.2f} ms with; the callable's own cost {own * 1e6:.3f} us; "
          f"overhead {per_call * 1e6:.3f} us per call (target under 1 us)")


def threads():
    template = open(os.path.join(SRC, "datfiles", "spatial", "cross_spring_pivot_study.dat")).read()
    variants = [flexmb.variant(template, t=(0.15 + 0.02 * k) * 1e-3) for k in range(16)]
    serial = best(lambda: [flexmb.static(v, nev=4) for v in variants], repeat=3)
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        parallel = best(lambda: list(pool.map(lambda v: flexmb.static(v, nev=4), variants)), repeat=3)
    print(f"threads: 16 pivot variants (static, 4 frequencies) {serial * 1e3:.1f} ms in one thread, "
          f"{parallel * 1e3:.1f} ms in two: {serial / parallel:.2f}x on {os.cpu_count()} cores (the GIL released)")


def result_reading():
    m = flexmb.read(os.path.join(SRC, "datfiles", "straight_guidance.dat"))
    r = flexmb.simulate(m, t_end=0.2, intervals=20000)
    view = best(lambda: r.x, number=10000)
    copy = best(lambda: np.array(r.x), number=100)
    print(f"reading results: x is {r.x.shape[0]} x {r.x.shape[1]} ({r.x.nbytes / 1e6:.1f} MB); handing it out "
          f"{view * 1e6:.2f} us (a view: owns its data {r.x.flags.owndata}, shares memory with the next "
          f"{np.shares_memory(r.x, r.x)}), copying it {copy * 1e6:.0f} us")


if __name__ == "__main__":
    print(f"flexmb Python front end, python {sys.version.split()[0]}, numpy {np.__version__}")
    call_overhead()
    usersig_overhead()
    result_reading()
    threads()
