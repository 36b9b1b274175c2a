"""The worked example of docs/python.md runs (on a small scene), and the page shows it as it is."""
import os
import pathlib
import subprocess
import sys

from conftest import SOURCE_DIR, write_cornell

EXAMPLE = SOURCE_DIR / "python" / "examples" / "spp_study.py"


def test_the_spp_study_writes_its_plot_and_one_line_per_budget(tmp_path):
    scene = write_cornell(tmp_path, 24)
    plot = tmp_path / "spp.png"
    run = subprocess.run([sys.executable, str(EXAMPLE), str(scene), str(plot)], check=True,
                         capture_output=True, text=True, env=dict(os.environ, MPLBACKEND="Agg"))
    lines = run.stdout.splitlines()
    assert [line.split()[0] for line in lines] == ["4", "16", "64"]
    assert plot.read_bytes().startswith(b"\x89PNG")


def test_docs_python_md_shows_the_example_verbatim():
    page = (SOURCE_DIR / "docs" / "python.md").read_text()
    body = EXAMPLE.read_text().split('"""\n', 1)[1]  # without its docstring
    assert body.strip() in page
