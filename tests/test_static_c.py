"""Every C folder `fricgen emit` writes (tests/emit_variants.py) checked as a product team checks
it: the strict warnings with -Wfloat-equal under gcc and clang, cppcheck's MISRA C:2012 addon and
clang-tidy's bugprone checks. A finding fails unless its rule is a documented deviation: the
tables of docs/reference/c-api.md, section "MISRA C:2012 deviations", are the one list."""
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from emit_variants import emit_every_variant
from fricgen.codegen.cbuild import STRICT_WARNINGS

DOCS = Path(__file__).resolve().parent.parent / "docs" / "reference" / "c-api.md"
SECTION = "## MISRA C:2012 deviations"
RULE = re.compile(r"(\d+\.\d+|bugprone-[a-z-]+)\b")
TIDY_CHECKS = "-*,bugprone-*"


def documented_deviations():
    """{MISRA rule or clang-tidy check: (where, why)} from the tables of the manual's section."""
    section = DOCS.read_text().split(f"\n{SECTION}\n", 1)[1].split("\n## ", 1)[0]
    rows = {}
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")] if line.startswith("|") else []
        match = RULE.match(cells[0].strip("`")) if len(cells) == 3 else None
        if match:
            rows[match.group(1)] = (cells[1], cells[2])
    return rows


def misra_findings(folder):
    """[(file, line, rule)] of cppcheck --addon=misra on ``folder``; other output lines as rule
    None (an addon that fails, a configuration error)."""
    proc = subprocess.run(["cppcheck", "--addon=misra", "--std=c99", "--quiet",
                           "--template={file}|{line}|{id}", str(folder)],
                          capture_output=True, text=True, timeout=300)
    found = []
    for line in (proc.stdout + proc.stderr).splitlines():
        m = re.fullmatch(r"(.*)\|(\d+)\|misra-c2012-(\d+\.\d+)", line.strip())
        if m:
            found.append((Path(m.group(1)).name, int(m.group(2)), m.group(3)))
        elif line.strip():
            found.append((line.strip(), 0, None))
    return found


def tidy_findings(folder):
    """[(file, line, check)] of clang-tidy's bugprone checks on each .c of ``folder``, its headers
    included; errors as check None."""
    found = []
    for src in sorted(folder.glob("*.c")):
        proc = subprocess.run(["clang-tidy", f"-checks={TIDY_CHECKS}", "-header-filter=.*", str(src),
                               "--", "-std=c99", f"-I{folder}"], capture_output=True, text=True, timeout=300)
        for line in proc.stdout.splitlines():
            m = re.match(r"(.*?):(\d+):\d+: (warning|error): .*?(?:\[([\w.,-]+)\])?$", line)
            if m:
                check = m.group(4) if m.group(3) == "warning" else None
                found.append((Path(m.group(1)).name, int(m.group(2)), check))
    return sorted(set(found))


def _misra_addon_runs(tmp_path):
    probe = tmp_path / "probe.c"
    probe.write_text("union u { int i; float f; };\n")
    return any(rule == "19.2" for _, _, rule in misra_findings(tmp_path))


needs_cppcheck = pytest.mark.skipif(shutil.which("cppcheck") is None,
                                    reason="cppcheck not installed (apt-get install cppcheck)")
needs_tidy = pytest.mark.skipif(shutil.which("clang-tidy") is None,
                                reason="clang-tidy not installed (apt-get install clang-tidy)")


@pytest.fixture(scope="module")
def variants(tmp_path_factory, bench, model10, axis2_model):
    return emit_every_variant(tmp_path_factory.mktemp("variants"), bench, model10, axis2_model)


@pytest.fixture(scope="module")
def misra(tmp_path_factory):
    if shutil.which("cppcheck") is None:
        pytest.skip("cppcheck not installed (apt-get install cppcheck)")
    if not _misra_addon_runs(tmp_path_factory.mktemp("misra_probe")):
        pytest.skip("cppcheck's misra addon (addons/misra.py) is missing or does not run")
    return documented_deviations()


def test_the_variants_cover_every_implementation_and_runtime_source(variants):
    sources = {p.name for folder in variants.values() for p in folder.glob("*.c")}
    assert {"fric_fast.c", "fric_ctrl.c", "fric_adapt.c", "fric_bytes.c", "fric_sqrt.c", "fric_exp_neg.c",
            "fric_elm_sigmoid.c", "fric_elm_sine.c", "fm_adapt.c", "tx.c", "sl.c", "sf.c", "cg.c",
            "cf.c"} <= sources
    heads = " ".join((folder / f"{n}.h").read_text() for folder in variants.values()
                     for n in ("fm", "gb", "gx", "fa", "fx") if (folder / f"{n}.h").exists())
    for option in ("dtype=float activation_impl=libm", "dtype=float activation_impl=fast", "dtype=q15",
                   "dtype=q31", "with_controller=1"):
        assert option in heads


def test_every_file_of_every_variant_is_reached_from_a_model(variants):
    """What ``codegen.package.reached_files`` reaches from a folder's models is every C file an
    emit wrote there, so a later emit into the folder removes no runtime file a model uses (it
    removes those no model reaches: a re-emit without --adapt)."""
    from fricgen.codegen.package import reached_files
    for variant, folder in variants.items():
        texts = {p.name: p.read_text() for p in folder.glob("*.[ch]")}
        if variant != "runtime":                       # the whole runtime, no model
            assert reached_files(texts) == set(texts), variant


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_every_variant_compiles_without_a_warning_under_the_strict_flags(variants, cc):
    """-Wfloat-equal included: the C compares no float with == or != (NaN tests use isnan)."""
    if shutil.which(cc) is None:
        pytest.skip(f"{cc} not installed")
    assert "-Wfloat-equal" in STRICT_WARNINGS and "-Werror" in STRICT_WARNINGS
    failures = {}
    for variant, folder in variants.items():
        for src in sorted(folder.glob("*.c")):
            proc = subprocess.run([cc, "-std=c99", *STRICT_WARNINGS, "-c", src.name, "-o", "/dev/null"],
                                  cwd=folder, capture_output=True, text=True)
            if proc.returncode != 0 or proc.stderr:
                failures[f"{variant}/{src.name}"] = proc.stderr[-600:]
    assert not failures, failures


def test_the_deviation_tables_give_where_and_why_for_each_rule():
    rows = documented_deviations()
    assert "15.5" in rows and "bugprone-easily-swappable-parameters" in rows
    assert all(where and why for where, why in rows.values()), rows


@needs_cppcheck
def test_misra_findings_are_all_documented_deviations(variants, misra):
    seen, undocumented = set(), []
    for variant, folder in variants.items():
        for fname, line, rule in misra_findings(folder):
            seen.add(rule)
            if rule not in misra:
                undocumented.append(f"{variant}/{fname}:{line}: {rule}")
    assert not undocumented, "\n".join(undocumented[:40])
    # and no deviation is stale: each documented MISRA rule is met somewhere
    assert {r for r in misra if not r.startswith("bugprone")} == seen


@needs_cppcheck
def test_the_misra_check_reports_a_rule_that_is_not_a_deviation(tmp_path, misra):
    """The check above is not vacuous: an if ... else if without else (15.7) and a modified
    parameter (17.8) are found and are not deviations."""
    (tmp_path / "bad.c").write_text("int bad(int x);\nint bad(int x)\n{\n    if (x > 0) {\n        x = 1;\n"
                                    "    } else if (x < 0) {\n        x = -1;\n    }\n    return x;\n}\n")
    rules = {rule for _, _, rule in misra_findings(tmp_path)}
    assert {"15.7", "17.8"} <= rules and not {"15.7", "17.8"} & set(misra)


@needs_tidy
def test_clang_tidy_bugprone_findings_are_all_documented_deviations(variants):
    deviations = documented_deviations()
    seen, undocumented = set(), []
    for variant, folder in variants.items():
        for fname, line, check in tidy_findings(folder):
            seen.add(check)
            if check not in deviations:
                undocumented.append(f"{variant}/{fname}:{line}: {check}")
    assert not undocumented, "\n".join(undocumented[:40])
    assert {r for r in deviations if r.startswith("bugprone")} == seen


@needs_tidy
def test_clang_tidy_reports_a_check_that_is_not_a_deviation(tmp_path):
    """A macro with an unparenthesized negative constant (the finding fixed in fric_fast.c)."""
    (tmp_path / "bad.c").write_text("#define NEG -1.5f\nfloat bad(float x);\nfloat bad(float x) { return x * NEG; }\n")
    checks = {check for _, _, check in tidy_findings(tmp_path)}
    assert "bugprone-macro-parentheses" in checks
    assert "bugprone-macro-parentheses" not in documented_deviations()
