"""tools/check_docs.py: reruns the quoted commands, fails on a differing value, rewrites on --update."""
import os
import subprocess
import textwrap

import pytest

import check_docs as cd

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "tools", "check_docs.py")

DOC = textwrap.dedent("""\
    # A doc

    <!-- check first
      err: ^midpoint .* (\\S+) m$ | x 1e3
      at: diverged at t = (\\S+) s
      ahead: = err / 0.5 | tol 1%
    -->
    ```sh
    build/clothsim compare scenes/x.yaml --still 1 -o x.png
    ```

    The error is 3.3<!--=first.err--> mm, RK4 diverges at 0.042<!--=first.at--> s, and midpoint
    is 6.7<!--=first.ahead-->x the half millimetre.

    <!-- check slow [full]
      n: ^n = (\\d+)
    -->
    ```sh
    build/clothsim bench --slow
    ```

    It counts 50<!--=slow.n--> steps.
    """)


@pytest.fixture
def tree(tmp_path):
    """A build dir whose clothsim prints fixed lines, and a doc quoting them."""
    build = tmp_path / "build"
    build.mkdir()
    fake = build / "clothsim"
    fake.write_text("#!/bin/sh\n"
                    "case \"$*\" in *--slow*) echo 'n = 50';; *) echo 'midpoint 2e-4 0.00334 m';"
                    " echo 'rk4: diverged at t = 0.0424 s' >&2; touch x.png;; esac\n")
    fake.chmod(0o755)
    doc = tmp_path / "doc.md"
    doc.write_text(DOC)
    return build, doc


def check(build, doc, *flags):
    return subprocess.run(["/usr/bin/python3", SCRIPT, "--build", str(build), str(doc), *flags],
                          capture_output=True, text=True)


def test_values_that_round_to_the_quoted_figures_hold(tree):
    build, doc = tree
    r = check(build, doc)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "3 quoted values checked, 0 differ" in r.stdout
    assert "[full] checks skipped" in r.stdout


def test_a_differing_value_fails_naming_it_and_update_rewrites_it_at_its_figures(tree):
    build, doc = tree
    doc.write_text(DOC.replace("3.3<!--=first.err-->", "4.1<!--=first.err-->"))
    r = check(build, doc)
    assert r.returncode == 1
    assert "DIFFERS" in r.stdout and "first.err: quoted 4.1, printed 3.34" in r.stdout, r.stdout
    r = check(build, doc, "--update")
    assert r.returncode == 0, r.stdout
    assert "3.3<!--=first.err--> mm" in doc.read_text()
    assert check(build, doc).returncode == 0


def test_full_runs_the_slow_checks_and_a_wrong_count_fails(tree):
    build, doc = tree
    doc.write_text(DOC.replace("50<!--=slow.n-->", "60<!--=slow.n-->"))
    assert check(build, doc).returncode == 0  # not run by default
    r = check(build, doc, "--full")
    assert r.returncode == 1 and "slow.n: quoted 60" in r.stdout, r.stdout


def test_a_mark_naming_no_check_is_a_malformed_doc(tree):
    build, doc = tree
    doc.write_text(DOC + "\nAnd 7<!--=first.nothing--> more.\n")
    r = check(build, doc)
    assert r.returncode == 2
    assert "names no value of a check" in r.stderr


def test_a_command_that_fails_fails_the_check(tree):
    build, doc = tree
    doc.write_text(DOC.replace("build/clothsim compare", "build/clothsim compare --nope; exit 2; build/clothsim"))
    r = check(build, doc)
    assert r.returncode == 1 and "gave exit 2" in r.stdout, r.stdout


def test_the_tolerance_is_the_quoted_figures_unless_stated():
    assert cd.holds("3.3", 3.34, 0.0) and not cd.holds("3.3", 3.36, 0.0)
    assert cd.holds("0.042", 0.0424, 0.0) and not cd.holds("0.042", 0.0426, 0.0)
    assert cd.holds("4.0e-7", 4.04e-7, 0.0) and not cd.holds("4.0e-7", 4.1e-7, 0.0)
    assert cd.holds("24", 24.4, 0.0) and not cd.holds("24", 25.6, 0.0)
    assert cd.holds("24", 25.6, 0.1)
    assert cd.written("4.0e-7", 4.26e-7) == "4.3e-7"
    assert cd.written("3.3", 0.421) == "0.42"
    assert cd.written("24", 31.4) == "31"


def test_the_repository_docs_are_well_formed():
    """Every mark in README.md and docs/report.md names a check's value; every check parses."""
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    for name in cd.DEFAULT_DOCS:
        with open(os.path.join(root, name)) as f:
            checks, marks = cd.parse(name, f.read())
        assert marks, f"{name} marks no quoted number"
        assert {c.tier for c in checks.values()} & {"default"}, f"{name}: no check runs by default"


def test_pointers_to_missing_files_sections_and_anchors_are_named_with_their_line(tmp_path, monkeypatch):
    (tmp_path / "docs").mkdir()
    (tmp_path / "src").mkdir()
    (tmp_path / "docs" / "a.md").write_text("# A\n\n## Lanes\n\nSee [b](b.md) and `src/x.h`.\n")
    (tmp_path / "docs" / "b.md").write_text("# B\n\nBack to [a](a.md#lanes), [gone](a.md#gone).\n")
    (tmp_path / "src" / "x.h").write_text('// docs/a.md, "Lanes" holds; docs/a.md, "Nowhere" does not;\n'
                                           "// src/y.h is not here.\n")
    monkeypatch.setattr(cd, "ROOT", str(tmp_path))
    problems = cd.check_pointers()
    assert any(p.startswith("docs/b.md:3:") and "has no heading #gone" in p for p in problems), problems
    assert any(p.startswith("src/x.h:1:") and 'has no section "Nowhere"' in p for p in problems), problems
    assert any(p.startswith("src/x.h:2:") and "src/y.h does not exist" in p for p in problems), problems
    assert len(problems) == 3, problems


def test_a_timed_figure_is_judged_by_its_csv_with_the_timings_left_out(tmp_path):
    tree, new = tmp_path / "tree.csv", tmp_path / "new.csv"
    tree.write_text("integrator,dt,cpu_seconds,wall_seconds,rms_error,reason\n"
                    "rk4,0.001,1.5,1.6,1.234567e-08,\n")
    new.write_text("integrator,dt,cpu_seconds,wall_seconds,rms_error,reason\n"
                   "rk4,0.001,2.5,2.9,1.2345670001e-08,\n")
    assert cd.same_csv(tree, new) == ""  # the load moves only the timings
    new.write_text("integrator,dt,cpu_seconds,wall_seconds,rms_error,reason\n"
                   "rk4,0.001,1.5,1.6,1.3e-08,\n")
    assert cd.same_csv(tree, new) == "line 2, rms_error: '1.3e-08', the tree's '1.234567e-08'"
    new.write_text("integrator,dt,cpu_seconds,wall_seconds,rms_error,reason\n")
    assert cd.same_csv(tree, new) == "0 rows, the tree's 1"
