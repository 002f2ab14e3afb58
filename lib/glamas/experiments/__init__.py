"""The chapter's experiments and the studies beyond it, one package each (its experiment, analysis and
plots modules), and the registry that lists them."""
