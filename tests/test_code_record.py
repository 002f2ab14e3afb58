"""The record of code (glamas.sources.code_digest) is the same on every supported Python, and a
record made in another form, or on another Python, is reported as such rather than as changed code."""

from glamas import provenance, results, sources
from glamas.experiments import registry
from glamas.paths import REPO, RESULTS

PINNED = REPO / "tests" / "data" / "pinned_module.py"
PINNED_DIGEST = "5d0984c32581dd66"
"""code_digest of PINNED, the same on Python 3.11, 3.12 and 3.13 (whose ``ast.dump`` texts differ:
3.12 added fields, 3.13 leaves empty ones out, and 3.12 parses a nested f-string format spec with an
extra empty text). A change of the form changes it: then change CODE_FORM too, and re-record."""


def test_the_record_of_a_fixed_module_is_pinned():
    assert sources.code_digest(PINNED) == PINNED_DIGEST


def test_comments_docstrings_and_layout_do_not_count_and_a_change_of_what_it_does_does(tmp_path):
    text = PINNED.read_text()
    moved = tmp_path / "moved.py"
    moved.write_text(text.replace('    """One step."""\n', "").replace("  # the collision penalty", "\n\n    # another comment") + "\n\n")
    changed = tmp_path / "changed.py"
    changed.write_text(text.replace("-10.0", "-1.0"))
    assert sources.code_digest(moved) == PINNED_DIGEST
    assert sources.code_digest(changed) != PINNED_DIGEST


def _committed_record():
    experiment = next(e for e in registry.experiments() if e.name == "single_gla")
    config = experiment.paper_scale()
    return results.stored_provenance(experiment.file(RESULTS)), provenance.record(config)


def test_every_committed_result_records_the_form_its_code_is_compared_in():
    stored, current = _committed_record()
    assert stored["code_form"] == sources.CODE_FORM == current["code_form"]


def test_a_record_in_another_form_is_called_that_not_changed_code():
    stored, current = _committed_record()
    older = {**stored, "code_form": None, "code": {module: "0" * 16 for module in stored["code"]}}
    said = provenance.mismatch(older, current)
    assert "older form" in said and "changed since" not in said


def test_a_record_of_other_code_made_on_another_python_names_both_pythons():
    stored, current = _committed_record()
    module = sorted(stored["code"])[0]
    other = {**stored, "python": "3.99", "code": {**stored["code"], module: "0" * 16}}
    said = provenance.mismatch(other, current)
    assert f"glamas/{module}" in said and "Python 3.99" in said and f"Python {current['python']}" in said
