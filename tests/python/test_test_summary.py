# SPDX-License-Identifier: GPL-3.0-or-later
"""The README test command's verdict (scripts/test_summary.py --strict, as scripts/test.sh runs it)
on small junit files in ctest's and pytest's formats (as CMake 3.25-4.4 and pytest 7 write them):
a tier that did not run, a test not run because its fixture's setup failed, and a skip that is not
an expected one each fail the command, and every skip's reason is printed."""

import importlib.util
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "test_summary.py"
spec = importlib.util.spec_from_file_location("test_summary", SCRIPT)
summary = importlib.util.module_from_spec(spec)
spec.loader.exec_module(summary)

# One ctest test of every tier, all passed (labels as the CMake files give them).
TIER_TESTS = [("HapticLoop.RunsAndBoundsTheForce", "cpp"), ("fuzz_falcon_packet", "fuzz"), ("pytest", "python"),
              ("install_prefix_import", "python"), ("blender_test_live_session", "blender"),
              ("blender_window_test_live_pace", "blender"), ("farm_openjd_job", "farm"), ("package_build", "package")]


def ctest_case(name, labels, status="run", skipped=None, out="", failure=False):
    inner = f'<skipped message="{skipped}"/>' if skipped else ""
    inner += '<failure message="Failed"/>' if failure else ""
    return (f'<testcase name="{name}" classname="{name}" time="1" status="{status}">{inner}<properties>'
            f'<property name="cmake_labels" value="{labels}"/></properties><system-out>{out}</system-out></testcase>')


def ctest_file(tmp_path, cases):
    path = tmp_path / "ctest-junit.xml"
    path.write_text(f'<?xml version="1.0" encoding="UTF-8"?><testsuite name="x" tests="{len(cases)}">'
                    + "".join(cases) + "</testsuite>")
    return path


def all_tiers(replace=None):
    replace = replace or {}
    return [replace.get(name, ctest_case(name, labels)) for name, labels in TIER_TESTS if replace.get(name, "") is not None]


def pytest_file(tmp_path, cases, skipped=0, failures=0, errors=0):
    path = tmp_path / "pytest-junit.xml"
    path.write_text(f'<?xml version="1.0" encoding="utf-8"?><testsuites><testsuite name="pytest" errors="{errors}" '
                    f'failures="{failures}" skipped="{skipped}" tests="{len(cases)}">' + "".join(cases)
                    + "</testsuite></testsuites>")
    return path


PASSED = '<testcase classname="test_api" name="test_ok" time="0.1"/>'


def verdict(capsys, *args):
    rc = summary.main(["test_summary.py", *map(str, args)])
    return rc, capsys.readouterr().out


def test_every_tier_passed_is_a_strict_pass(tmp_path, capsys):
    rc, out = verdict(capsys, "--strict", "--all-tiers", ctest_file(tmp_path, all_tiers()),
                      pytest_file(tmp_path, [PASSED, PASSED]))
    assert rc == 0, out
    assert "pytest (pytest cases): 2 passed, 0 failed, 0 skipped" in out and "strict: passed" in out


def test_a_tier_that_did_not_run_fails_the_whole_suite_but_not_a_selection(tmp_path, capsys):
    cases = all_tiers({"blender_window_test_live_pace": None})  # xvfb-run missing: never registered
    junit = ctest_file(tmp_path, cases)
    rc, out = verdict(capsys, "--strict", "--all-tiers", junit, pytest_file(tmp_path, [PASSED]))
    assert rc == 1 and "Blender window (Xvfb): none run" in out
    assert "strict: the Blender window (Xvfb) tier did not run" in out
    rc, out = verdict(capsys, "--strict", junit, tmp_path / "pytest-junit.xml")  # ctest -R ...: a selection
    assert rc == 0, out
    # A tier whose every test skipped did not run either (and its skips are not expected ones).
    cases = all_tiers({"package_build": ctest_case("package_build", "package", "notrun", "SKIP_RETURN_CODE=77",
                                                   "SKIP: cannot build the wheel on this machine: no CPython")})
    rc, out = verdict(capsys, "--strict", "--all-tiers", ctest_file(tmp_path, cases), tmp_path / "pytest-junit.xml")
    assert rc == 1 and "strict: the package tier did not run: every test in it skipped" in out
    assert "skipped (unexpected) package_build: SKIP: cannot build the wheel on this machine: no CPython" in out


def test_a_test_not_run_because_its_setup_failed_counts_as_failed(tmp_path, capsys):
    cases = all_tiers() + [
        ctest_case("package_zip", "package", "fail", out="setup broken", failure=True),
        ctest_case("package_blender_4.2", "package", "notrun", "Fixture dependency failed",
                   "Failed test dependencies: package_zip"),
        ctest_case("package_missing", "package", "notrun", "Unable to find executable", "Unable to find executable: x")]
    rc, out = verdict(capsys, "--strict", "--all-tiers", ctest_file(tmp_path, cases), pytest_file(tmp_path, [PASSED]))
    assert rc == 1
    assert "package: 1 passed, 3 failed, 0 skipped" in out, out
    assert "not run (counted as failed) package_blender_4.2: Not Run (Fixture dependency failed)" in out
    assert "strict: 3 failed" in out
    # The tally is the same without --strict; only the exit status is ctest's alone.
    rc, out = verdict(capsys, ctest_file(tmp_path, cases), tmp_path / "pytest-junit.xml")
    assert rc == 0 and "package: 1 passed, 3 failed, 0 skipped" in out


def test_an_unexpected_skip_fails_with_its_reason_printed(tmp_path, capsys):
    module_skip = ('<testcase classname="" name="test_bake" time="0"><skipped message="collection skipped">'
                   "('/src/tests/python/test_bake.py', 25, 'Skipped: pyopenvdb is missing: apt-get install "
                   "python3-openvdb')</skipped></testcase>")
    case_skip = ('<testcase classname="test_falcon" name="test_open" time="0"><skipped type="pytest.skip" '
                 'message="a Falcon is plugged in">/src/tests/python/test_falcon.py:29: a Falcon is plugged in'
                 "</skipped></testcase>")
    gtest_skip = ctest_case("GlDeviceChoice.SoftwareFallback", "cpp", "notrun", "SKIP_REGULAR_EXPRESSION_MATCHED",
                            "[  SKIPPED ] this machine has a GPU: NVIDIA H200")
    junit = ctest_file(tmp_path, all_tiers() + [gtest_skip])
    rc, out = verdict(capsys, "--strict", "--all-tiers", junit, pytest_file(tmp_path, [PASSED, module_skip, case_skip],
                                                                               skipped=2))
    assert rc == 1
    assert "pytest (pytest cases): 1 passed, 0 failed, 2 skipped" in out
    assert "skipped (unexpected) test_bake: pyopenvdb is missing: apt-get install python3-openvdb" in out
    assert "skipped (unexpected) test_falcon::test_open: a Falcon is plugged in" in out
    assert "skipped (unexpected) GlDeviceChoice.SoftwareFallback: [  SKIPPED ] this machine has a GPU" in out
    assert out.count("strict: unexpected skip:") == 3
    rc, _ = verdict(capsys, junit, tmp_path / "pytest-junit.xml")  # printed, not judged
    assert rc == 0


@pytest.mark.parametrize("test_id, reason, expected", [
    ("test_haptic_strokes::test_strokes_are_passive_with_the_simulation_at_60_hz[air-1.2]",
     "slow machine: 16^3 steps took 41 ms (median)", True),
    ("test_haptic_strokes::test_strokes_are_passive_at_the_largest_gain_slowed_and_fast[water-1000.0-60 Hz]",
     "slow machine: 16^3 steps took 41 ms (median)", True),
    ("test_haptic_strokes::test_strokes_are_passive_at_the_largest_gain_slowed_and_fast[water-1000.0-5 Hz]",
     "slow machine: 16^3 steps took 41 ms (median)", False),
    ("test_haptic_strokes::test_strokes_are_passive_with_the_simulation_at_60_hz[air-1.2]", "no GL", False),
    ("test_haptic_feel::test_the_force_follows_the_fluid_and_reverses_with_the_motion",
     "slow machine: the fluid lived 2.1 s of its own time in 60 s", True),
    ("test_haptic_seed_feel::test_pushed_steadily_the_hand_feels_the_drag_against_the_motion",
     "slow machine: 48^3 steps took 0.47 s (median)", True),
    ("test_haptic_seed_feel::test_at_rest_the_hand_feels_buoyancy", "slow machine: x", False),
])
def test_only_the_listed_skips_are_expected(tmp_path, capsys, test_id, reason, expected):
    module, name = test_id.split("::")
    case = (f'<testcase classname="{module}" name="{name}" time="1"><skipped type="pytest.skip" message="{reason}">'
            f"x.py:1: {reason}</skipped></testcase>")
    rc, out = verdict(capsys, "--strict", "--all-tiers", ctest_file(tmp_path, all_tiers()),
                      pytest_file(tmp_path, [PASSED, case], skipped=1))
    assert rc == (0 if expected else 1), out
    assert f"skipped ({'expected: ' if expected else 'unexpected'}" in out and reason in out


def test_a_pytest_tier_without_its_report_or_a_run_without_junit_fails(tmp_path, capsys):
    rc, out = verdict(capsys, "--strict", ctest_file(tmp_path, all_tiers()), tmp_path / "absent.xml")
    assert rc == 1 and "the pytest tier ran but left no report" in out
    rc, out = verdict(capsys, "--strict", tmp_path / "absent.xml")
    assert rc == 1 and "ctest did not write its junit file" in out
    assert verdict(capsys, tmp_path / "absent.xml")[0] == 0
    assert verdict(capsys, "--strickt", tmp_path / "absent.xml")[0] == 2


def test_the_expected_skips_name_their_reason():
    for pattern, prefix, why in summary.EXPECTED_SKIPS:
        assert "::" in pattern and len(prefix) >= 10 and len(why) > 10, (pattern, prefix, why)
