"""The README and docs say what the code does: its command table names every sub-command of
`trikecert` with every option, its configuration table every setting, its demo session is what
`trikecert demo` prints, and the layouts list every package, docs page and template folder."""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
from pathlib import Path

from app.cli import build_parser
from app.config import Settings

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")
BIN = Path(sys.executable).parent
_CELL_BORDER = re.compile(r"(?<!\\)\|")  # `officer\|admin` is one cell


def section(heading: str) -> str:
    """The README's text under this `## ` heading, up to the next one."""
    start = README.index(f"\n## {heading}\n")
    end = README.find("\n## ", start + 1)
    return README[start : end if end != -1 else None]


def table_rows(text: str) -> list[list[str]]:
    """The cells of each row of the Markdown tables in the text (header and rule left out)."""
    rows = []
    for line in text.splitlines():
        if line.startswith("| ") and not line.startswith("| ---"):
            rows.append([cell.strip() for cell in _CELL_BORDER.split(line)[1:-1]])
    return rows[1:] if rows else rows


def sub_commands() -> dict[str, set[str]]:
    """Every sub-command of `trikecert` and its long options."""
    for action in build_parser()._actions:
        if isinstance(action, argparse._SubParsersAction):
            return {
                name: {o for a in parser._actions for o in a.option_strings if o.startswith("--")}
                - {"--help"}
                for name, parser in action.choices.items()
            }
    raise AssertionError("trikecert has no sub-commands")


def documented_commands() -> dict[str, str]:
    """Each sub-command the README's command table names -> the text of its row."""
    documented: dict[str, str] = {}
    for first, *rest in table_rows(section("The `trikecert` command")):
        for usage in re.findall(r"`([^`]+)`", first):
            name = usage.removeprefix("trikecert ").split()[0]
            documented[name] = " ".join([first, *rest])
    return documented


def test_the_readme_command_table_names_every_sub_command_and_option() -> None:
    commands, documented = sub_commands(), documented_commands()
    assert sorted(commands.keys() - documented.keys()) == [], "sub-commands missing from the README"
    assert sorted(documented.keys() - commands.keys()) == [], "the README names commands that do not exist"
    rows = list(documented.values())
    for name, options in commands.items():
        row = documented[name]
        if "the options above" in row:  # update-station: create-station's, one row up
            row += rows[rows.index(row) - 1]
        assert sorted(o for o in options if o not in row) == [], name


def test_the_readme_configuration_table_names_every_setting() -> None:
    documented = [row[0].strip("`") for row in table_rows(section("Configuration"))]
    settings = [f"TRIKECERT_{name.upper()}" for name in Settings.model_fields]
    assert len(documented) == len(set(documented)), "a setting is listed twice"
    assert sorted(set(settings) - set(documented)) == [], "settings missing from the README"
    assert sorted(set(documented) - set(settings)) == [], "the README names settings that do not exist"


def test_trikecert_demo_prints_the_readmes_session_and_says_how_to_get_a_key_again(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if not k.startswith("TRIKECERT_")}
    env["TRIKECERT_DATABASE_URL"] = f"sqlite:///{tmp_path / 'trikecert.db'}"

    def demo() -> list[str]:
        done = subprocess.run(
            [BIN / "trikecert", "demo"], env=env, cwd=tmp_path, capture_output=True, text=True, timeout=120
        )
        assert done.returncode == 0, done.stderr
        return done.stdout.splitlines()

    first = demo()
    block = section("A session with the study's vehicle").split("$ .venv/bin/trikecert demo\n", 1)[1]
    shown = [line.removeprefix("    ") for line in block.split("\n\n", 1)[0].splitlines()]
    assert first[:-1] == shown[:-1]  # the last line is the station's key, new every time
    assert re.fullmatch(r"tks_[A-Za-z0-9_-]{43}", first[-1])

    again = demo()
    assert again[0] == "the demo vehicle BDG 252 QH is already loaded; nothing changed"
    assert "trikecert rotate-station-key 'Demo weighbridge (Agbara)'" in again[-1]
    assert "rotate-station-key 'Demo weighbridge (Agbara)'" in section("A session with the study's vehicle")


def test_the_readmes_layout_lists_every_package_test_folder_and_docs_page() -> None:
    layout = section("Project layout")
    packages = [p.name for p in (ROOT / "app").iterdir() if (p / "__init__.py").is_file()]
    assert sorted(p for p in packages if f"  {p}/ " not in layout) == []
    test_folders = [p.name for p in (ROOT / "tests").iterdir() if p.is_dir() and p.name != "__pycache__"]
    assert sorted(f for f in test_folders if f"{f}/" not in layout) == []
    docs = layout.split("\ndocs/", 1)[1].split("\n.ci/", 1)[0]
    pages = [p.name + ("/" if p.is_dir() else "") for p in (ROOT / "docs").iterdir()]
    assert sorted(p for p in pages if p not in docs) == []


def test_docs_web_lists_every_template_folder() -> None:
    web = (ROOT / "docs" / "web.md").read_text(encoding="utf-8")
    listed = re.search(r"`templates/\{([a-z_,]+)\}/`", web)
    assert listed, "docs/web.md no longer lists the template folders as templates/{...}/"
    folders = [p.name for p in (ROOT / "templates").iterdir() if p.is_dir()]
    assert sorted(set(folders) - set(listed[1].split(","))) == [], "template folders docs/web.md lacks"
    assert sorted(set(listed[1].split(",")) - set(folders)) == [], "docs/web.md names missing folders"


def test_the_accessibility_tests_reach_axe_core_only_through_the_fixture_that_skips() -> None:
    """A test that read the script's path itself died with FileNotFoundError on a fresh clone."""
    allowed = {ROOT / "tests" / "web" / "webtools.py", ROOT / "tests" / "web" / "conftest.py", Path(__file__)}
    readers = [p for p in (ROOT / "tests").rglob("*.py") if p not in allowed and "AXE_PATH" in p.read_text()]
    assert readers == []
