"""Tables for a reader: a header and rows of cells that print as aligned text in a terminal and
render as a table in a notebook (and in the book built from the notebooks). A column of numbers is
right-aligned, any other left-aligned."""

import re

from glamas.errors import UserError

NUMBER = re.compile(r"^(?:[<>]=? ?)?(?:[-+]?\d|[-+]?\.\d|-$|[-+]?inf|nan)", re.IGNORECASE)
"""A cell that reads as a number, a bound (> 1000) or a number's placeholder ('-', inf, nan)."""


def _numeric(rows, column: int) -> bool:
    return bool(rows) and all(NUMBER.match(row[column]) for row in rows)


def _line(cells) -> str:
    """One Markdown table row; a "|" inside a cell escaped."""
    return "| " + " | ".join(str(cell).replace("|", "\\|") for cell in cells) + " |"


def markdown(header, rows) -> str:
    """A Markdown table of ``rows`` (each a list of cells) under ``header``."""
    rows = [[str(cell) for cell in row] for row in rows]
    rule = "|" + "".join("---:|" if _numeric(rows, k) else "---|" for k in range(len(header)))
    return "\n".join([_line(header), rule, *map(_line, rows)])


class Table(str):
    """A table that is also its text: as a string (printed, searched, split into lines) its rows
    aligned in columns; shown as a notebook cell's value, a rendered Markdown table (:func:`markdown`)."""

    header: list[str]
    rows: list[list[str]]

    def __new__(cls, header, rows):
        header = [str(cell) for cell in header]
        rows = [[str(cell) for cell in row] for row in rows]
        if any(len(row) != len(header) for row in rows):
            raise UserError(f"every row of a table needs {len(header)} cells, one per column")
        widths = [max(map(len, column)) for column in zip(header, *rows)]
        right = [_numeric(rows, k) for k in range(len(header))]
        text = "\n".join(
            "  ".join(cell.rjust(width) if numeric else cell.ljust(width)
                      for cell, width, numeric in zip(row, widths, right)).rstrip()
            for row in [header, *rows])
        table = super().__new__(cls, text)
        table.header, table.rows = header, rows
        return table

    def _repr_markdown_(self) -> str:
        return markdown(self.header, self.rows)

    def _repr_pretty_(self, printer, cycle) -> None:
        printer.text(str(self))


def labelled(values: dict, *, name: str = "", value: str = "value") -> Table:
    """A two-column :class:`Table` of a mapping: each label beside its value."""
    return Table([name, value], [[label, v] for label, v in values.items()])
