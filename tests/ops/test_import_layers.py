"""The layers of app/ hold, read from the source (docs/architecture.md): the import-linter contracts
in pyproject.toml are kept, no two packages import each other (directly or in a circle), the kits
app/web/ and app/api/ import no domain package, and the pure core app/stability/ imports nothing of
the app. Every import counts: inside functions and under TYPE_CHECKING too."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable
from pathlib import Path

import grimp
import pytest
from importlinter import configuration
from importlinter.application.use_cases import lint_imports

ROOT = Path(__file__).resolve().parents[2]
# What a kit may use besides itself: the modules at the foot of app/ (and the API kit, for the pages).
KERNEL = {
    "app",
    "app.config",
    "app.db",
    "app.errors",
    "app.grants",
    "app.i18n",
    "app.group_commit",
    "app.ids",
    "app.migrate",
    "app.numbers",
    "app.prepared",
    "app.stability",
    "app.text",
    "app.wording",
}
KITS = {"app.web": KERNEL | {"app.api"}, "app.api": KERNEL}


@pytest.fixture(scope="module")
def graph() -> grimp.ImportGraph:
    """Every import between the modules of app/, none excluded."""
    return grimp.build_graph("app", exclude_type_checking_imports=False, cache_dir=None)


def top_package(module: str) -> str:
    """app.inspections.views -> app.inspections; app.main -> app.main."""
    return ".".join(module.split(".")[:2])


def imports_out_of(graph: grimp.ImportGraph, package: str) -> Iterable[tuple[str, str, int]]:
    """(importer, imported, line) of each import from inside `package` to a module outside it."""
    for importer in sorted(module for module in graph.modules if top_package(module) == package):
        for imported in sorted(graph.find_modules_directly_imported_by(importer)):
            if top_package(imported) != package:
                for detail in graph.get_import_details(importer=importer, imported=imported):
                    yield importer, imported, int(detail["line_number"])


def test_the_import_contracts_in_pyproject_are_kept(capsys: pytest.CaptureFixture[str]) -> None:
    """import-linter's report names each import that breaks a layer, and the chain it starts."""
    configuration.configure()
    kept = lint_imports(config_filename=str(ROOT / "pyproject.toml"), cache_dir=None, no_logo=True)
    assert kept, capsys.readouterr().out


def test_no_two_packages_of_app_import_each_other(graph: grimp.ImportGraph) -> None:
    """The package graph of app/ has no cycle; a failure names one import of each edge of a cycle."""
    example: dict[tuple[str, str], str] = {}
    needs: dict[str, set[str]] = defaultdict(set)
    for package in sorted({top_package(module) for module in graph.modules}):
        for importer, imported, line in imports_out_of(graph, package):
            edge = (package, top_package(imported))
            if edge[1] != "app":  # the root's __init__: the version, importing nothing
                needs[package].add(edge[1])
                example.setdefault(edge, f"{importer} -> {imported} (l.{line})")
    cycles = _cycles(needs)
    assert not cycles, "\n".join(
        " -> ".join([*cycle, cycle[0]])
        + "\n"
        + "\n".join(f"    {example[(a, b)]}" for a, b in zip(cycle, cycle[1:] + cycle[:1], strict=True))
        for cycle in cycles
    )


def _cycles(needs: dict[str, set[str]]) -> list[list[str]]:
    """One cycle through each strongly connected group of packages (Tarjan, then a walk inside it)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    groups: list[set[str]] = []

    def visit(package: str) -> None:
        index[package] = low[package] = len(index)
        stack.append(package)
        for other in sorted(needs.get(package, ())):
            if other not in index:
                visit(other)
                low[package] = min(low[package], low[other])
            elif other in stack:
                low[package] = min(low[package], index[other])
        if low[package] == index[package]:
            group: set[str] = set()
            while (member := stack.pop()) != package:
                group.add(member)
            groups.append(group | {package})

    for package in sorted(needs):
        if package not in index:
            visit(package)
    cycles = []
    for group in (group for group in groups if len(group) > 1):
        start = min(group)
        path, seen = [start], {start}
        while (step := min(needs[path[-1]] & group)) not in seen:
            path.append(step)
            seen.add(step)
        cycles.append(path[path.index(step) :])
    return cycles


@pytest.mark.parametrize("kit", sorted(KITS))
def test_a_kit_imports_no_domain_package(graph: grimp.ImportGraph, kit: str) -> None:
    """app/web/ and app/api/ hold what every page or endpoint shares: no capability's modules."""
    allowed = KITS[kit]
    wrong = [
        f"{importer} -> {imported} (l.{line})"
        for importer, imported, line in imports_out_of(graph, kit)
        if top_package(imported) not in allowed
    ]
    assert not wrong, "\n".join(wrong)


def test_the_pure_core_imports_nothing_of_the_app(graph: grimp.ImportGraph) -> None:
    """app/stability/ knows no HTTP, SQL, HTML or PDF, nor any other module of the app."""
    wrong = [
        f"{importer} -> {imported} (l.{line})"
        for importer, imported, line in imports_out_of(graph, "app.stability")
    ]
    assert not wrong, "\n".join(wrong)
