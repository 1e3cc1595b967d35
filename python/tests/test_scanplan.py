"""The Python module against the library's own ground truth: the CLI's plan of the
bundled part, a part whose size is known, errors from bad input, numpy round trips."""

import json
import os
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import scanplan

EXAMPLES = os.environ["SCANPLAN_EXAMPLES"]
TEST_DATA = os.environ["SCANPLAN_TEST_DATA"]
PART = os.path.join(TEST_DATA, "nist_ftc_11_asme1_ap242-e1.stp")


@pytest.fixture(scope="module")
def part():
    return scanplan.import_part(PART)


@pytest.fixture(scope="module")
def plan(part):
    return scanplan.plan(part)


def comparable(plan_json):
    """plan.json but the seconds it records, which differ from run to run, and the part's
    path as given, which a file writes relative to itself (its absolute path stays)."""
    summary = plan_json["summary"]
    summary.pop("seconds")
    summary.pop("stage_seconds")
    plan_json["part"].pop("file")
    return plan_json


def test_the_bundled_example_s_gdt_plans_as_the_command_line_does(tmp_path):
    """The bundled part and spec without its global task (GD&T from the file, markers,
    registration), planned by the scanplan CLI and from Python: the same plan.json."""
    spec_file = tmp_path / "spec.yaml"
    with open(os.path.join(EXAMPLES, "specs", "ctc01.yaml")) as f:
        bundled = f.read()
    assert "  - {type: global}\n" in bundled
    spec_file.write_text(bundled.replace("  - {type: global}\n", ""))
    part_file = os.path.join(EXAMPLES, "parts", "nist_ctc_01_asme1_ap242-e1.stp")
    out = tmp_path / "out"
    subprocess.run([os.environ["SCANPLAN_CLI"], "-q", "plan", part_file, "--spec", str(spec_file),
                    "-o", str(out), "--no-report"], check=True, stdout=subprocess.DEVNULL)
    plan = scanplan.plan(scanplan.import_part(part_file), scanplan.load_spec(str(spec_file)))
    with open(out / "plan.json") as f:
        cli = json.load(f)
    assert len(plan.views) == len(cli["views"]) > 0
    assert comparable(plan.to_json()) == comparable(cli)


def test_a_part_reads_with_its_size_and_its_mesh_viewed_in_place(part):
    # NIST FTC 11: a 63 mm disc, 3 mm thick, with eight faces (tests/data/README.md).
    assert part.format == "STEP"
    assert part.face_count == 8
    size = part.bounds[1] - part.bounds[0]
    np.testing.assert_allclose(size, [62.976, 62.988, 3.015], atol=1e-3)
    vertices = part.vertices
    assert vertices.shape[1] == 3 and vertices.dtype == np.float64
    assert not vertices.flags.writeable and not vertices.flags.owndata  # a view, not a copy
    assert part.triangles.max() < len(vertices)
    assert set(np.unique(part.triangle_faces)) == set(range(1, 9))
    # The mesh's area, summed in numpy, is the part's.
    a, b, c = (vertices[part.triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()
    assert area == pytest.approx(part.area, rel=1e-3)


def test_a_plan_and_its_arrays(plan, part):
    assert len(plan.views) > 0
    assert plan.views.shape == (len(plan.view_ids), 4, 4)
    rotations = plan.views[:, :3, :3]
    np.testing.assert_allclose(rotations @ rotations.transpose(0, 2, 1),
                               np.broadcast_to(np.eye(3), rotations.shape), atol=1e-9)
    assert plan.samples.shape == plan.normals.shape == (len(plan.measured), 3)
    np.testing.assert_allclose(np.linalg.norm(plan.normals, axis=1), 1, atol=1e-9)
    assert plan.measured_share == pytest.approx(plan.measured.mean())
    doc = plan.to_json()
    assert doc["summary"]["measured"] == int(plan.measured.sum())
    assert [v["id"] for v in doc["views"]] == plan.view_ids


def test_views_round_trip_through_numpy(plan, part):
    """The plan's views as an (n, 4, 4) array simulate exactly as the plan's own."""
    own = scanplan.simulate(part, plan)
    given = scanplan.simulate(part, plan, views=plan.views.copy())
    assert len(own) == len(given) == len(plan.views)
    for a, b in zip(own, given):
        assert len(a["points"]) > 0
        np.testing.assert_array_equal(a["points"], b["points"])
        np.testing.assert_array_equal(a["faces"], b["faces"])


def test_every_rest_orientation_simulates_in_its_own_placement(part):
    """Views planned in the part's other rest orientations record clouds of the part as it
    stood for them."""
    plan = scanplan.plan(part, {"part": {"rest": "all"}}, registration=False)
    orientations = plan.to_json()["orientations"]
    assert len(orientations) > 1
    clouds = scanplan.simulate(part, plan)
    assert all(len(c["points"]) > 0 for c in clouds)
    # The face the part stands on at first (datum A, its flatness) is seen once turned up.
    bottom = next(t["faces"][0] for t in part.tolerances if t["type"] == "flatness")
    assert any(bottom in c["faces"] for c in clouds)


def test_write_read_and_verify(plan, part, tmp_path):
    path = str(tmp_path / "plan.json")
    scanplan.write_plan(plan, path)
    back = scanplan.read_plan(path)
    np.testing.assert_allclose(back.views, plan.views, atol=1e-12)
    check = scanplan.verify(back, part)
    assert check["coverage_differences"] == 0
    scanplan.write_report(plan, part, str(tmp_path / "report.html"))
    assert (tmp_path / "report.html").stat().st_size > 0
    # The part with its 32 mm bore made 0.1 mm larger in the file is not the plan's.
    with open(PART, encoding="latin-1") as f:
        step = f.read()
    bore = "CYLINDRICAL_SURFACE('',#739,16.);"
    assert bore in step
    changed = tmp_path / "changed.stp"
    changed.write_text(step.replace(bore, "CYLINDRICAL_SURFACE('',#739,16.05);"), encoding="latin-1")
    other = scanplan.import_part(str(changed))
    for call in (lambda: scanplan.verify(back, other), lambda: scanplan.inspect(back, other),
                 lambda: scanplan.write_program(back, other, str(tmp_path / "p.src"), "krl"),
                 lambda: scanplan.write_report(back, other, str(tmp_path / "other.html"))):
        with pytest.raises(scanplan.InputError, match="not the part the plan was made for"):
            call()
    assert not (tmp_path / "p.src").exists() and not (tmp_path / "other.html").exists()


def test_bad_input_raises_the_exit_codes_class(tmp_path):
    with pytest.raises(scanplan.InputError) as error:
        scanplan.import_part(str(tmp_path / "missing.stp"))
    assert error.value.exit_code == 2
    assert error.value.file.endswith("missing.stp")
    assert isinstance(error.value, scanplan.Error)
    with pytest.raises(scanplan.InputError, match="tasks must be a non-empty list"):
        scanplan.spec_from_dict({"tasks": []})
    with pytest.raises(scanplan.InputError, match="not a rigid motion"):
        part = scanplan.import_part(PART)
        scanplan.simulate(part, scanplan.plan(part, registration=False), views=np.zeros((1, 4, 4)))
    with pytest.raises(TypeError, match="spec: expected a scanplan.Spec, a dict or None, not int"):
        scanplan.plan(part, 5)


MARKED = {"gdt": "from-file", "markers": {"grid": 30, "on": "both"}, "tasks": [{"type": "gdt"}]}


def by_id(inspection):
    return {c["id"]: c for c in inspection["characteristics"]}


def test_a_bore_made_larger_inspects_larger_by_as_much(part, tmp_path):
    """FTC 11's GD&T, its views registered by markers, inspected virtually: with the 32 mm
    bore (face 4) made 0.2 mm larger, the bore measures 0.2 mm larger within its U and
    nothing else changes; and the inspection, with the spec the plan was made with, is the one
    `scanplan inspect` makes of the plan written, given the spec and the deviations as files."""
    plan = scanplan.plan(part, MARKED)
    bore = next(c["id"] for c in plan.to_json()["characteristics"]
                if c["kind"] == "diameter" and c["faces"] == [4])
    as_made = by_id(scanplan.inspect(plan, part, runs=5))
    deviations = [{"faces": [4], "diameter": 0.2}]
    larger = scanplan.inspect(plan, part, runs=5, deviations=deviations)
    made, grown = as_made[bore], by_id(larger)[bore]
    assert made["evaluated"] and made["true_value"] == pytest.approx(32)
    assert grown["true_value"] == pytest.approx(32.2)
    assert abs(grown["mean"] - 32.2) <= grown["uncertainty"]
    assert grown["mean"] - made["mean"] == pytest.approx(0.2, abs=1e-3)
    for k, c in by_id(larger).items():
        if k != bore and c["evaluated"]:
            assert c["mean"] == pytest.approx(as_made[k]["mean"], abs=1e-6)

    (tmp_path / "spec.yaml").write_text(json.dumps(MARKED))
    (tmp_path / "deviations.yaml").write_text(json.dumps({"deviations": deviations}))
    scanplan.write_plan(plan, str(tmp_path / "plan.json"))
    subprocess.run([os.environ["SCANPLAN_CLI"], "-q", "inspect", str(tmp_path / "plan.json"),
                    PART, "--spec", str(tmp_path / "spec.yaml"), "--runs", "5", "--deviations",
                    str(tmp_path / "deviations.yaml")], check=True, stdout=subprocess.DEVNULL)
    with open(tmp_path / "inspection.json") as f:
        assert json.load(f) == larger
    with pytest.raises(scanplan.InputError, match="deviation 1: the part has no face 99"):
        scanplan.inspect(plan, part, deviations=[{"faces": [99], "offset": 0.1}])
    with pytest.raises(scanplan.UsageError, match="expected drawn or registered"):
        scanplan.inspect(plan, part, icp="both")


def test_each_setup_s_robot_program_is_the_one_the_command_line_exports(part, tmp_path):
    """FTC 11 in both its rest orientations in an ABB cell: each setup's RAPID program written
    from Python is the one `scanplan export --setup K` writes from the plan file, but for the
    line naming where it comes from; a plan of two setups without one named, a setup it does
    not have, and a format no controller runs are refused, and nothing is written."""
    spec = {"part": {"rest": "all"}, "tasks": [{"type": "global"}],
            "cell": {"robot": {"preset": "abb-irb4600-60-205", "base": {"position": [-1000, 0, 0]}},
                     "mount": {"position": [0, 0, 150]}}}
    plan = scanplan.plan(part, spec)
    setups = plan.to_json()["orientations"]
    assert len(setups) == 2
    scanplan.write_plan(plan, str(tmp_path / "plan.json"))
    for k, setup in enumerate(setups, start=1):
        mine, theirs = tmp_path / f"py{k}.mod", tmp_path / f"cli{k}.mod"
        made = scanplan.write_program(plan, part, str(mine), "rapid", setup=k)
        assert sorted(made["views"]) == sorted(setup["views"])
        assert made["unreached"] == [] and made["uncleared"] == [] and made["seconds"] > 0
        subprocess.run([os.environ["SCANPLAN_CLI"], "-q", "export", str(tmp_path / "plan.json"),
                        PART, "--format", "rapid", "--setup", str(k), "-o", str(theirs)],
                       check=True, stdout=subprocess.DEVNULL)
        lines = [f.read_text().replace(f"cli{k}", f"py{k}").splitlines() for f in (theirs, mine)]
        assert len(lines[0]) == len(lines[1]) > 10
        differ = [a for a, b in zip(*lines) if a != b]
        assert len(differ) == 1 and "from" in differ[0] and f"setup {k} of 2" in differ[0]
    refused = tmp_path / "refused.mod"
    with pytest.raises(scanplan.UsageError, match="2 rest orientations, each a program"):
        scanplan.write_program(plan, part, str(refused), "rapid")
    with pytest.raises(scanplan.UsageError, match="the plan has 2 setups, not 3"):
        scanplan.write_program(plan, part, str(refused), "rapid", setup=3)
    with pytest.raises(scanplan.UsageError, match="expected krl, rapid, fanuc, urscript or json"):
        scanplan.write_program(plan, part, str(refused), "gcode", setup=1)
    assert not refused.exists()


def test_a_spec_from_a_dict_and_progress(part):
    spec = scanplan.spec_from_dict({"scanner": "laser-line", "tasks": [{"type": "global"}]})
    assert spec.scanner == "laser-line"
    stages = []
    plan = scanplan.plan(part, spec, registration=False,
                         progress=lambda stage, fraction: stages.append((stage, fraction)))
    assert len(plan.views) > 0
    assert stages and all(0 <= f <= 1 for _, f in stages)
    assert "laser-line" in scanplan.scanner_presets()


def test_planning_releases_the_gil(part):
    """The main thread runs Python while another thread plans: were the GIL held for the
    whole plan, its next turn would come only as the plan ends."""
    started = threading.Event()
    times = {}

    def run():
        started.set()
        times["plan_start"] = time.perf_counter()
        scanplan.plan(part, {"scanner": "laser-line"})  # about 0.3 s
        times["plan_done"] = time.perf_counter()

    thread = threading.Thread(target=run)
    thread.start()
    started.wait()
    times["main_turn"] = time.perf_counter()
    thread.join()
    planning = times["plan_done"] - times["plan_start"]
    assert times["main_turn"] - times["plan_start"] < 0.5 * planning


def test_a_raising_progress_callback_is_raised_after_planning(part):
    def fail(stage, fraction):
        raise RuntimeError("stop")

    with pytest.raises(RuntimeError, match="stop"):
        scanplan.plan(part, registration=False, progress=fail)


def test_the_example_script_plots(tmp_path):
    script = os.path.join(EXAMPLES, "python", "plan_and_plot.py")
    figure = tmp_path / "coverage.png"
    done = subprocess.run([sys.executable, script, PART, "-o", str(figure)],
                          capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert "figure" in done.stdout
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_study_plans_each_row_and_keeps_a_broken_parts_error(tmp_path):
    """scanplan.study runs the command's study (docs/study.md): each good row's plan is
    there with its views, the broken part's rows say why, and a missing study file raises
    InputError with the command's exit code."""
    (tmp_path / "broken.stp").write_text("not a STEP file\n")
    (tmp_path / "study.yaml").write_text(
        "parts: [%s, broken.stp]\nscanners: laser-line\nregistration: false\n" % PART)
    rows = scanplan.study(tmp_path / "study.yaml", out=tmp_path / "out", jobs=2)
    assert [row["status"] for row in rows] == ["ok", "failed"]
    for row in rows[:1]:
        plan = scanplan.read_plan(str(tmp_path / "out" / "plans" / row["plan"] / "plan.json"))
        assert int(row["views"]) == len(plan.view_ids) > 0
    assert "not a STEP file" in rows[1]["error"]
    with pytest.raises(scanplan.InputError) as missing:
        scanplan.study(tmp_path / "missing.yaml", out=tmp_path / "out2")
    assert missing.value.exit_code == 2
