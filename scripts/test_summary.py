#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The README test command's last lines: passed, failed and skipped per tier, so a tier that was
skipped, or never registered (a missing tool), shows instead of hiding in a green total.

    test_summary.py CTEST_JUNIT [PYTEST_JUNIT]

CTEST_JUNIT is ctest's --output-junit file; PYTEST_JUNIT is pytest's --junitxml file (the pytest
tier is one ctest test: its cases are counted from pytest's own report when it ran). Standard
library only; prints and exits 0 (the test command's exit status is ctest's).
"""

import sys
import xml.etree.ElementTree as ET
from pathlib import Path

# (tier, how to recognise its ctest tests), in the order printed; every tier is always listed.
TIERS = (
    ("GoogleTest", lambda name, labels: "cpp" in labels and not name.startswith("fuzz_")),
    ("fuzz", lambda name, labels: name.startswith("fuzz_")),
    ("pytest", lambda name, labels: name == "pytest"),
    ("python other", lambda name, labels: "python" in labels and name != "pytest"),
    ("Blender headless", lambda name, labels: name.startswith("blender_test_")),
    ("Blender window (Xvfb)", lambda name, labels: name.startswith("blender_window_test_")),
    ("farm", lambda name, labels: "farm" in labels),
    ("package", lambda name, labels: "package" in labels),
)


def _status(case: ET.Element) -> str:
    if case.find("failure") is not None or case.find("error") is not None or case.get("status") == "fail":
        return "failed"
    if case.find("skipped") is not None or case.get("status") in ("notrun", "disabled"):
        return "skipped"
    return "passed"


def ctest_cases(path: Path):
    """(name, labels, status, skip reason) for each ctest test in the junit file."""
    for case in ET.parse(path).getroot().iter("testcase"):
        labels = set()
        for prop in case.iter("property"):
            if prop.get("name") == "cmake_labels":
                labels = set(filter(None, (prop.get("value") or "").split(";")))
        reason = ""
        if _status(case) == "skipped":  # the test's own last words say why (e.g. 'SKIP: no CPython 3.13 ...')
            out = [line.strip() for line in (case.findtext("system-out") or "").splitlines() if line.strip()]
            said = [line for line in out if "skip" in line.lower()]
            reason = (said or out or [""])[-1][:200]
        yield case.get("name", ""), labels, _status(case), reason


def pytest_counts(path: Path):
    """({'passed': n, 'failed': n, 'skipped': n, 'expected failures': n}, [expected failure lines])
    from pytest's junit file, or None. A strict xfail (junit: skipped of type pytest.xfail) is a
    known defect its test names, not a skipped test: counted apart and listed with its reason."""
    if not path or not path.is_file():
        return None
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == "testsuite" else list(root.iter("testsuite"))
    total = sum(int(s.get("tests", 0)) for s in suites)
    failed = sum(int(s.get("failures", 0)) + int(s.get("errors", 0)) for s in suites)
    skipped = sum(int(s.get("skipped", 0)) for s in suites)
    xfails = []
    for case in root.iter("testcase"):
        mark = case.find("skipped")
        if mark is not None and mark.get("type") == "pytest.xfail":
            xfails.append(f"{case.get('classname', '')}.{case.get('name', '')}: {mark.get('message', '')}")
    counts = {"passed": total - failed - skipped, "failed": failed, "skipped": skipped - len(xfails),
              "expected failures": len(xfails)}
    return counts, xfails


def main(argv):
    if len(argv) < 2 or not Path(argv[1]).is_file():
        print("== summary: no ctest results to count (ctest did not write its junit file)")
        return 0
    counts = {tier: {"passed": 0, "failed": 0, "skipped": 0, "registered": 0} for tier, _ in TIERS}
    reasons = []
    pytest_ran = False
    for name, labels, status, reason in ctest_cases(Path(argv[1])):
        tier = next((t for t, match in TIERS if match(name, labels)), None)
        if tier is None:
            tier = "other"
            counts.setdefault(tier, {"passed": 0, "failed": 0, "skipped": 0, "registered": 0})
        counts[tier]["registered"] += 1
        counts[tier][status] += 1
        if status == "skipped":
            reasons.append(f"{name}: {reason or 'skipped (its output says why)'}")
        if tier == "pytest" and status != "skipped":
            pytest_ran = True
    found = pytest_counts(Path(argv[2])) if len(argv) > 2 and pytest_ran else None
    cases, xfails = found if found is not None else (None, [])
    if cases is not None:  # one ctest test: count its cases instead
        counts["pytest"].update(cases)
    print("== summary per tier: passed, failed, skipped")
    total = {"passed": 0, "failed": 0, "skipped": 0}
    for tier, c in counts.items():
        unit = " (pytest cases)" if tier == "pytest" and cases is not None else ""
        if c["registered"] == 0:
            print(f"  {tier}: none run (not registered or not selected: see the configure output)")
            continue
        known = f", {c['expected failures']} expected failures" if c.get("expected failures") else ""
        print(f"  {tier}{unit}: {c['passed']} passed, {c['failed']} failed, {c['skipped']} skipped{known}")
        for k in total:
            total[k] += c[k]
    for r in reasons:
        print(f"  skipped {r}")
    for x in xfails:
        print(f"  expected failure (a known defect; strict: it fails the run once it passes) {x}")
    known = f", {len(xfails)} expected failures" if xfails else ""
    print(f"total: {total['passed']} passed, {total['failed']} failed, {total['skipped']} skipped{known}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
