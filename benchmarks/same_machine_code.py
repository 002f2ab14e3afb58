"""Whether glamas's inliner (:mod:`glamas.inlining`, numba's without its copies) compiles the same
machine code as numba's own: every registered learner's run kernels compiled twice (``python -m glamas.precompile``'s tasks), each time in a
fresh process with an empty numba cache, once with each inliner, and their assembly compared (a
digest of it, with numba's count of compilations taken out of the symbols). A run kernel's
assembly holds its whole episode loop and everything compiled into it.

``python -m benchmarks.same_machine_code`` (about three minutes on 2 cores); exit status 1 when any
kernel differs.
"""

import json
import os
import subprocess
import sys
import tempfile

from glamas import errors

COMPILE_AND_DIGEST = """
import hashlib, json, re, sys
import glamas
from glamas import inlining, precompile
from glamas.learners import registry
from numba.core import inline_closurecall
if sys.argv[1] == "numba":
    inline_closurecall.InlineWorker.inline_function = inlining.NUMBA_INLINE_FUNCTION
digests = {}
for names in precompile.learner_groups():
    precompile.compile_learners(names)
    learner = registry.get(names[0])  # the learners of a group share these kernels
    for kernel in (learner.kernel, learner.two_agent_kernel):
        for number, signature in enumerate(getattr(kernel, "signatures", ())):
            # once per kernel: numba emits the assembly from the module again at every call, and
            # LLVM's code generation changes the module it emits from
            assembly = re.sub(r"B\\d+v\\d+", "B", kernel.inspect_asm(signature))
            digests[f"{kernel.__module__}.{kernel.__name__} #{number}"] = hashlib.sha256(assembly.encode()).hexdigest()
print(json.dumps(digests))
"""
"""Run in a fresh process: compile every learner's kernels with the inliner named by argv[1]
('glamas' or 'numba') and print the digest of each run kernel's assembly, as JSON."""


def digests(inliner: str) -> dict:
    """Each learner's run kernels' assembly digests, compiled with ``inliner`` from an empty cache."""
    with tempfile.TemporaryDirectory(prefix="glamas-same-code-") as cache:
        done = subprocess.run([sys.executable, "-c", COMPILE_AND_DIGEST, inliner], capture_output=True, text=True,
                              env={**os.environ, "NUMBA_CACHE_DIR": cache}, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> int:
    ours, numbas = digests("glamas"), digests("numba")
    print(f"{'run kernel, signature':48} {'glamas inliner':18} {'numba inliner':18} same")
    for kernel in sorted(ours.keys() | numbas.keys()):
        mine, theirs = ours.get(kernel, "-"), numbas.get(kernel, "-")
        print(f"{kernel:48} {mine[:16]:18} {theirs[:16]:18} {'yes' if mine == theirs else 'NO'}")
    return 0 if ours == numbas else 1


if __name__ == "__main__":
    errors.run(main)
