"""docs/notebooks/report.ipynb: stored without outputs, and makes every figure docs/report.md shows.

(ctest's Notebook.ReportFiguresFromPython executes it; this holds what executing cannot see.)"""
import json
import os
import re

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NOTEBOOK = os.path.join(ROOT, "docs", "notebooks", "report.ipynb")
REPORT = os.path.join(ROOT, "docs", "report.md")

# Each image docs/report.md shows -> the file the notebook writes for it (report_figures.sh's names).
FIGURES = {
    "drape_compare.png": "clip_frame.png",
    "report_sheet.png": "sheet.png",
    "report_stability_ks.png": "stability_ks.png",
    "report_stability_kd.png": "stability_kd.png",
    "report_energy_lanes.png": "energy_lanes.png",
    "report_energy.png": "energy.png",
    "report_ks.png": "ks.png",
    "report_kd.png": "kd.png",
    "bench_drape_smooth.png": "wp_cloth.png",
    "report_fixed_point_stability.png": "stability_fp.png",
    "report_fixed_point.png": "fixed_point.png",
    "report_families_energy.png": "families_energy.png",
}


def cells():
    with open(NOTEBOOK) as f:
        return json.load(f)["cells"]


def test_the_notebook_is_stored_without_outputs():
    for cell in cells():
        if cell["cell_type"] == "code":
            assert cell["outputs"] == [] and cell["execution_count"] is None, "".join(cell["source"])[:80]


def test_every_figure_of_the_report_is_written_and_shown_by_a_cell():
    with open(REPORT) as f:
        shown = re.findall(r"!\[[^\]]*\]\(images/([^)]+)\)", f.read())
    assert sorted(shown) == sorted(FIGURES), "a figure added to or gone from docs/report.md: map it here"
    code = ["".join(c["source"]) for c in cells() if c["cell_type"] == "code"]
    for image in shown:
        name = FIGURES[image]
        # written and shown in one cell: out() and show(), or energy_lines(), which does both
        assert any(f'"{name}"' in src and ("show(" in src or "energy_lines(" in src) for src in code), (image, name)
