"""The claim ledger: README.md's copy matches the committed results, and --check/--write work."""

import subprocess
import sys

import pytest

from glamas import claims, ledger

README = f"# title\n\n{ledger.START}\nold table\n{ledger.END}\n\n## next\n"


def test_the_readme_ledger_matches_the_committed_results():
    done = subprocess.run([sys.executable, "-m", "glamas.ledger", "--check"], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr


def test_check_reports_a_stale_readme_in_one_line_and_write_refreshes_it(monkeypatch, tmp_path, capsys):
    readme = tmp_path / "README.md"
    readme.write_text(README)
    monkeypatch.setattr(ledger, "README", readme)
    monkeypatch.setattr(ledger, "markdown", lambda *experiments: "new table")
    assert ledger.main(["--check"]) == 1
    assert capsys.readouterr().out.strip().count("\n") == 0
    assert ledger.main(["--write"]) == 0
    assert readme.read_text() == README.replace("old table", "new table")
    assert ledger.main(["--check"]) == 0


def test_the_readme_needs_one_pair_of_markers():
    with pytest.raises(ValueError, match="one <!-- ledger:start -->"):
        ledger.readme_with("table", "no markers here")
    with pytest.raises(KeyError, match="no experiment with claims named \\['nonexistent'\\]"):
        ledger.markdown("nonexistent")


def test_every_experiment_with_claims_has_a_ledger_entry():
    assert set(ledger.with_claims()) == set(claims.experiments())
