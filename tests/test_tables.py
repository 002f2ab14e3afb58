"""glamas.tables: a table prints as aligned text and renders in a notebook as a Markdown table,
numbers right-aligned, text left-aligned, a "|" in a cell escaped."""

import pytest

from glamas.tables import Table, labelled, markdown


def test_a_table_is_its_aligned_text_and_renders_as_markdown():
    table = Table(["learner", "steps", "note"], [["MMDP", 12.5, "a|b"], ["2observe", "-", "ok"]])
    assert table.splitlines() == ["learner   steps  note",
                                  "MMDP       12.5  a|b",
                                  "2observe      -  ok"]
    assert "MMDP" in table and str(table) == table
    assert table._repr_markdown_().splitlines() == ["| learner | steps | note |", "|---|---:|---|",
                                                    "| MMDP | 12.5 | a\\|b |", "| 2observe | - | ok |"]


def test_a_row_of_the_wrong_width_is_refused():
    with pytest.raises(ValueError, match="every row of a table needs 2 cells"):
        Table(["a", "b"], [["only one"]])


def test_a_mapping_becomes_a_table_of_labels_and_values():
    assert markdown(["x", "value"], [["steps", 11]]) == labelled({"steps": 11}, name="x")._repr_markdown_()
