"""Experiment definitions: a config, a run, an analysis and the plots of each of the chapter's experiments."""
