"""Compile seconds per kernel: what ``python -m glamas.precompile`` compiles, done here in one
process from an empty numba cache, with numba's compile events recorded (numba.core.event). Each
compiled function's own time (wall time: run it on a quiet machine) is its compile event less
those of the functions it compiled inside it (a kernel calls functions compiled on their own, as
rng.next_u64 and qlearning.q_update); the pieces numba inlines (``inline="always"``) count in
the function they are inlined into.

Prints each precompile task's wall time (a learner's kernels, then each experiment's small run,
which compiles what is left and computes a little), the functions that took longest, and the total
CPU time of the process. ``--quick`` compiles the independent learners' kernels only.
"""

import atexit
import os
import shutil
import tempfile
import time

CACHE = tempfile.mkdtemp(prefix="glamas-compile-")
os.environ["NUMBA_CACHE_DIR"] = CACHE  # before numba is imported, so that every kernel compiles here
atexit.register(shutil.rmtree, CACHE, True)

from numba.core import event  # noqa: E402 (after the cache is chosen)

from glamas import errors  # noqa: E402

SHOWN = 15
"""How many of the longest compiled functions are listed."""


class CompileTimes(event.Listener):
    """numba's compile events, as own seconds per compiled function (module docstring)."""

    def __init__(self):
        super().__init__()
        self.own, self.open = {}, []

    def on_start(self, ev):
        function = ev.data["dispatcher"].py_func
        self.open.append([f"{function.__module__}.{function.__qualname__}", time.perf_counter(), 0.0])

    def on_end(self, ev):
        name, start, inside = self.open.pop()
        seconds = time.perf_counter() - start
        self.own[name] = self.own.get(name, 0.0) + seconds - inside
        if self.open:
            self.open[-1][2] += seconds


def main():
    from benchmarks import timing

    quick = timing.quick(__doc__)
    times = CompileTimes()
    event.register("numba:compile", times)
    from glamas import precompile, small_runs

    tasks = [(", ".join(names), precompile.compile_learners, names) for names in precompile.learner_groups()]
    tasks += [(f"small run of {name}", precompile.compile_experiment, name) for name in small_runs.sizes()]
    if quick:
        tasks = [task for task in tasks if task[0] == "independent"]
    print(f"{'seconds':>8s}  task (one process, empty numba cache)")
    for label, task, argument in tasks:
        start = time.perf_counter()
        task(argument)
        print(f"{time.perf_counter() - start:8.1f}  {label}")
    print(f"\n{'own s':>8s}  compiled function (the {SHOWN} longest of {len(times.own)})")
    for name in sorted(times.own, key=times.own.get, reverse=True)[:SHOWN]:
        print(f"{times.own[name]:8.1f}  {name}")
    cpu = time.process_time()
    print(f"\nin all {sum(times.own.values()):.0f} s compiling (wall time), {cpu:.0f} s CPU time of this process")


if __name__ == "__main__":
    errors.run(main)
