"""The readable step of 2observe (Alg. 4) stays readable: what one step of two agents executes in
glamas.plain is a short read in few files. Measured by running the step: every function it calls,
counted in lines of code (docstrings and blank lines left out)."""

import ast
import random
import sys
from pathlib import Path

from benchmarks import kernels
from glamas.learners.two_observe import GLASettings
from glamas.plain import gridworld as plain_gridworld

LIBRARY = str(Path(plain_gridworld.__file__).parents[1])


def functions_called(step, *args) -> set:
    """(file, first line) of every named library function ``step(*args)`` runs."""
    called = set()

    def trace(frame, event, _):
        code = frame.f_code
        if event == "call" and code.co_filename.startswith(LIBRARY) and not code.co_name.startswith("<"):
            called.add((code.co_filename, code.co_firstlineno))

    before = sys.gettrace()
    sys.settrace(trace)
    try:
        return step(*args), called
    finally:
        sys.settrace(before)


def code_lines(file: str, first_line: int) -> int:
    """Lines of code of the function defined at ``first_line`` of ``file``, its docstring and blank
    lines left out."""
    source = Path(file).read_text()
    lines = source.splitlines()
    node = next(node for node in ast.walk(ast.parse(source)) if isinstance(node, ast.FunctionDef)
                and min([node.lineno] + [d.lineno for d in node.decorator_list]) == first_line)
    docstring = node.body[0] if ast.get_docstring(node) is not None else None
    skipped = range(docstring.lineno, docstring.end_lineno + 1) if docstring else ()
    return sum(1 for k in range(node.lineno, node.end_lineno + 1) if k not in skipped and lines[k - 1].strip())


def test_one_two_agent_2observe_step_reads_in_150_lines_of_2_files():
    # GLAs rewarded for coordinating, so that within a few steps the agents coordinate and yield
    workload = kernels.Workload("two_observe", 3, own=GLASettings(gla_feedback=((0.0, 0.0), (1.0, 1.0))))
    world = plain_gridworld.World(workload.gridmap(), workload.bounce, workload.rewards)
    step = plain_gridworld.two_observe(world, workload, random.Random(1))
    cells, done, called = list(world.starts), [False, False], set()
    for _ in range(2000):
        (cells, _, reached, _, _), more = functions_called(step, cells, done)
        called |= more
        done = [d or r for d, r in zip(done, reached)]
        if all(done):
            cells, done = list(world.starts), [False, False]
    files = {file for file, _ in called}
    lines = sum(code_lines(file, line) for file, line in called)
    assert len(files) <= 2 and lines <= 150, (sorted(files), lines)
    assert {Path(file).name for file in files} == {"gridworld.py", "gla.py"}
    yielded = plain_gridworld.yield_action.__code__
    assert (yielded.co_filename, yielded.co_firstlineno) in called  # the whole of Alg. 4 was read
