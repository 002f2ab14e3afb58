"""Fig. 6 (Section 4.2): experiment 1 once per context encoding, joint, absolute distance and deictic.
:mod:`.experiment` configures and runs it, :mod:`.analysis` compares the encodings' expected rewards and
:mod:`.plots` draws them; this face hands their names on (:mod:`glamas.experiments.faces`) and
registers Fig. 6 and the same experiment under the other readings of its box."""

import functools

from glamas.experiments.faces import face
from glamas.experiments.registry import SEED, Experiment, register
from glamas.experiments.single_gla.experiment import SingleGLAConfig
from glamas.experiments.state_encoding.analysis import encoding_claim_rows
from glamas.experiments.state_encoding.experiment import (BOX_READINGS, ENCODING_NAMES, EncodingConfig,
                                                          compare_encodings, encoding_arrays, encodings_from_arrays,
                                                          other_readings, readings_arrays, readings_from_arrays,
                                                          scaled_encodings)

__getattr__, __dir__ = face(__name__, __file__)

FIG6 = register(Experiment(
    "state_encoding", EncodingConfig, compare_encodings, scaled_encodings, SingleGLAConfig.runs,
    SingleGLAConfig.iterations,
    claim_rows=lambda results, config: encoding_claim_rows(results, other_box_readings(config), config.box),
    figures=("fig6",), copies=len(ENCODING_NAMES), to_arrays=encoding_arrays, from_arrays=encodings_from_arrays,
    small_run={"runs": 2, "iterations": 2000}, recompute_minutes=1))
"""Fig. 6's experiment: experiment 1 with each context, in Fig. 6's default box."""
FIG6_READINGS = register(Experiment(
    "state_encoding_readings", EncodingConfig, other_readings, scaled_encodings, SingleGLAConfig.runs,
    SingleGLAConfig.iterations, figures=("fig6_readings",), chapter=False,
    copies=len(ENCODING_NAMES) * (len(BOX_READINGS) - 1), to_arrays=readings_arrays, from_arrays=readings_from_arrays,
    small_run={"runs": 2, "iterations": 2000}, recompute_minutes=0.5))
"""Fig. 6's experiment under the readings of its box other than the default: what its claims are
also judged under."""


@functools.cache
def other_box_readings(config: EncodingConfig, seed: int = SEED) -> dict:
    """Fig. 6 under the box readings other than ``config``'s (box -> encoding -> result): at paper
    scale the committed result (its configuration and provenance checked), else computed at
    ``config``'s scale from the same seed (seconds). Once per process: the verdicts and the notebook
    read the same results."""
    return FIG6_READINGS.committed_or_run(config, seed)
