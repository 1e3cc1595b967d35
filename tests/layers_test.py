"""The layering rule (scripts/check-layers.py) on the tree, and on small trees that break it."""
import importlib.util
import pathlib
import shutil

import pytest

REPO = pathlib.Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("check_layers", REPO / "scripts" / "check-layers.py")
layers = importlib.util.module_from_spec(spec)
spec.loader.exec_module(layers)


def test_the_tree_has_no_upward_include_and_no_loose_file():
    assert layers.violations(REPO) == []


def write(root, rel, text=""):
    path = root / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


@pytest.fixture
def tree(tmp_path):
    """A small library: core, cad and planning, each including only downward."""
    write(tmp_path, "include/scanplan/core/geometry.h", "#pragma once\n")
    write(tmp_path, "include/scanplan/cad/part.h", "#include <scanplan/core/geometry.h>\n")
    write(tmp_path, "include/scanplan/planning/planner.h", "#include <scanplan/cad/part.h>\n")
    write(tmp_path, "include/scanplan/planning.h", "#include <scanplan/planning/planner.h>\n")
    write(tmp_path, "src/cad/part.cpp", '#include <scanplan/cad/part.h>\n#include "cad/brep.h"\n')
    write(tmp_path, "src/cad/brep.h", "#include <vector>\n")
    write(tmp_path, "src/planning/planner.cpp", '#include "cad/brep.h"\n#include <Eigen/Core>\n')
    return tmp_path


def test_a_tree_that_includes_only_downward_passes(tree):
    assert layers.violations(tree) == []


def test_a_deliberate_upward_include_fails(tree):
    write(tree, "src/cad/part.cpp", "#include <scanplan/planning/planner.h>\n")
    found = layers.violations(tree)
    assert len(found) == 1
    assert found[0].startswith("src/cad/part.cpp (cad) includes include/scanplan/planning/planner.h")
    assert "above it" in found[0]
    assert layers.main(["check-layers.py", str(tree)]) == 1


def test_an_upward_include_through_a_private_header_fails(tree):
    write(tree, "src/planning/stages.h", "#pragma once\n")
    write(tree, "src/cad/brep.h", '#include "planning/stages.h"\n')
    assert layers.violations(tree) == [
        "src/cad/brep.h (cad) includes src/planning/stages.h (planning, above it)"]


def test_an_include_between_parts_of_one_rung_fails(tree):
    write(tree, "include/scanplan/robot/cell.h", "#include <scanplan/sampling/sampling.h>\n")
    write(tree, "include/scanplan/sampling/sampling.h", "#pragma once\n")
    assert layers.violations(tree) == [
        "include/scanplan/robot/cell.h (robot) includes include/scanplan/sampling/sampling.h "
        "(sampling, on its rung)"]


def test_a_file_outside_a_part_folder_fails(tree):
    write(tree, "src/sweep.cpp", "#include <scanplan/cad/part.h>\n")
    write(tree, "include/scanplan/clustering.h", "#pragma once\n")
    assert sorted(layers.violations(tree)) == [
        "include/scanplan/clustering.h: in no part folder", "src/sweep.cpp: in no part folder"]


def test_a_folder_that_is_no_part_fails(tree):
    write(tree, "src/misc/helpers.cpp", "\n")
    assert layers.violations(tree) == ["src/misc/helpers.cpp: in no part folder"]


def test_the_checker_passes_on_a_copy_of_the_tree_and_fails_once_it_is_broken(tmp_path):
    for folder in ("src", "include"):
        shutil.copytree(REPO / folder, tmp_path / folder)
    assert layers.violations(tmp_path) == []
    view = tmp_path / "include/scanplan/core/view.h"
    view.write_text(view.read_text().replace(
        "#include <scanplan/core/geometry.h>",
        "#include <scanplan/core/geometry.h>\n#include <scanplan/scanner/sensor.h>"))
    assert layers.violations(tmp_path) == [
        "include/scanplan/core/view.h (core) includes include/scanplan/scanner/sensor.h "
        "(scanner, above it)"]
