"""Fig. 6's experiment (Section 4.2), its configuration and its run: experiment 1 once per
context encoding (joint, absolute distance, deictic), in a reading of Fig. 6's box L, the GLA
parameters recorded at log-spaced checkpoints."""

from dataclasses import dataclass, replace

import numpy as np

from glamas import checks, memory, portable
from glamas.experiments.state_encoding.analysis import expected_curves
from glamas.experiments.single_gla.experiment import PARAMETERS, SingleGLAConfig, SingleGLAResult, run, scaled
from glamas.errors import UserError


ENCODING_NAMES = ("joint", "absolute", "deictic")
BOX_READINGS = ("fig5", "two", "input_range")
"""Readings of Fig. 6's box L (eq. 14), which the chapter does not restate (:class:`EncodingConfig`)."""
INPUT_RANGE = {"joint": 1.0, "absolute": 2.0, "deictic": 2.0}
"""The largest |input| of each context's non-bias inputs: positions lie in [-1, 1], so
|xA - xB| lies in [0, 2] and x_self - x_other in [-2, 2]."""


def box_L(box: str, encoding: str, fig5_L: float) -> float:
    """L of eq. 14 for one encoding under a reading of Fig. 6's box (:data:`BOX_READINGS`):
    'fig5' Fig. 5's L for every encoding, 'two' L = 2 for every one, 'input_range' Fig. 5's L
    times the encoding's input range (:data:`INPUT_RANGE`: joint 1, absolute and deictic 2), the
    rule 2observe's box follows (a box that scales with the largest input)."""
    if box not in BOX_READINGS:
        raise UserError(f"box must be one of {list(BOX_READINGS)}, got {box!r}")
    return {"fig5": fig5_L, "two": 2.0, "input_range": fig5_L * INPUT_RANGE[encoding]}[box]


@dataclass(frozen=True)
class EncodingConfig:
    """Fig. 6 (Section 4.2): experiment 1 once per context encoding. Fig. 6 restates no setting:
    ``experiment`` holds Fig. 5's."""

    experiment: SingleGLAConfig = SingleGLAConfig()
    """Experiment 1's settings; each encoding's runs take its context and the L that ``box`` gives."""
    box: str = "fig5"
    """Fig. 6's box L (:func:`box_L`): 'fig5' (default), 'two' or 'input_range'. Fig. 6 is the same
    experiment with other contexts and was run without tuning the Boltzmann exploration, which the
    box caps (it bounds u.x / T); every encoding's best boundaries (x1 = x2, |x1 - x2| = 0.5) lie
    where L = 1 already lets them be sharp, so the reason for 2observe's wider box does not arise."""
    checkpoints: int = 48
    """Checkpoints log-spaced from iteration 10 to the last (with the start), where the GLA
    parameters are recorded and the expected reward of the learning curve is evaluated."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"checkpoints": 2})
        for name in ENCODING_NAMES:
            self.encoding(name)  # validates box, and init_scale against each encoding's L

    def encoding(self, name: str) -> SingleGLAConfig:
        """Experiment 1's configuration for the context ``name`` under this box reading."""
        return replace(self.experiment, context=name, L=box_L(self.box, name, self.experiment.L))

    def checkpoint_iterations(self) -> np.ndarray:
        """The iterations after which the parameters are recorded: 0 and ``checkpoints`` log-spaced
        ones from 10 (or the last iteration, if fewer) to the last (rounded, duplicates dropped)."""
        last = self.experiment.iterations
        spaced = np.rint(portable.geomspace(min(10, last), last, self.checkpoints)).astype(np.int64)
        return np.unique(np.concatenate([[0], spaced]))

    def memory_bytes(self) -> int:
        """Bytes of one encoding's runs: experiment 1's arrays, and the parameters and the expected
        reward at the start and at the checkpoints."""
        checkpoints = memory.per_run(self.experiment.runs, (self.checkpoints + 1) * (PARAMETERS + 1))
        return self.experiment.memory_bytes() + checkpoints


def compare_encodings(config: EncodingConfig, seed: int = 0, workers=None,
                      progress: str | None = None) -> dict:
    """Fig. 6: the same experiment with each context encoding (same seed, so run r of every
    encoding sees the same positions until their actions differ), the parameters recorded at the
    checkpoints and the team's expected reward computed there (:func:`.analysis.expected_curves`:
    seconds for the joint context, computed once here rather than by every reader of the result)."""
    results = {name: run(config.encoding(name), seed, workers, None if progress is None else f"{progress} ({name})",
                         config.checkpoint_iterations())
               for name in ENCODING_NAMES}
    return {name: replace(result, expected_reward=expected_curves(result)) for name, result in results.items()}


def encoding_arrays(results: dict) -> dict:
    """Fig. 6's result arrays as one flat dict ('<encoding>_<array>'), as its result file stores them."""
    return {f"{name}_{key}": value for name, res in results.items() for key, value in res.arrays().items()}


def encodings_from_arrays(config: EncodingConfig, arrays: dict) -> dict:
    """The inverse of :func:`encoding_arrays`: encoding name -> result (``config``'s for the encoding)."""
    keys = ("iteration", "reward", "params", "checkpoint", "checkpoint_params", "expected_reward")
    return {name: SingleGLAResult(config.encoding(name), *(arrays[f"{name}_{key}"] for key in keys))
            for name in ENCODING_NAMES}


def other_readings(config: EncodingConfig, seed: int = 0, workers=None, progress: str | None = None) -> dict:
    """Fig. 6 under each reading of its box other than ``config``'s (:data:`BOX_READINGS`), from the
    same seed: box -> encoding -> result. What its claims are also judged under."""
    return {box: compare_encodings(replace(config, box=box), seed, workers, None if progress is None else f"{progress} {box}")
            for box in BOX_READINGS if box != config.box}


def readings_arrays(readings: dict) -> dict:
    """:func:`other_readings`'s results as one flat dict ('<box>_<encoding>_<array>'), as its result file stores them."""
    return {f"{box}_{key}": value for box, results in readings.items() for key, value in encoding_arrays(results).items()}


def readings_from_arrays(config: EncodingConfig, arrays: dict) -> dict:
    """The inverse of :func:`readings_arrays`: box -> encoding -> result."""
    return {box: encodings_from_arrays(replace(config, box=box), {key.removeprefix(f"{box}_"): value
                                                                  for key, value in arrays.items() if key.startswith(f"{box}_")})
            for box in BOX_READINGS if box != config.box}


def scaled_encodings(runs: int, iterations: int, **settings) -> EncodingConfig:
    """Fig. 6 (with ``settings`` of :class:`EncodingConfig` changed) at ``runs`` and ``iterations``."""
    return EncodingConfig(scaled(runs, iterations), **settings)
