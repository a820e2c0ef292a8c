"""The Python code of docs/python.md (its tutorial) and of README.md (its Python section) runs as
written: block after block in one namespace, from a folder holding data_samples/ (and ../shared/ for
README's Cornell table), so the examples and the asserts in them stay true."""

import os
import re
import sys
import subprocess
import types

import pytest

from conftest import SHARED_DIR, SOURCE_DIR


def python_blocks(path, after=None):
    """The ```python blocks of a markdown file (those after the heading `after` when given)."""
    text = path.read_text()
    if after is not None:
        text = text[text.index(after):]
        following = re.search(r"\n## ", text[len(after):])
        text = text[: len(after) + following.start()] if following else text
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def run_blocks(blocks, folder, monkeypatch):
    """Runs the blocks in `folder`/repo, where data_samples/ is the source's and ../shared the shared data."""
    repo = folder / "repo"
    repo.mkdir()
    os.symlink(SOURCE_DIR / "data_samples", repo / "data_samples")
    os.symlink(SHARED_DIR, folder / "shared")
    monkeypatch.chdir(repo)
    namespace = {"__name__": "__docs__"}
    for i, block in enumerate(blocks):
        exec(compile(block, f"block {i + 1}", "exec"), namespace)


def test_the_tutorial_of_docs_python_md_runs(tmp_path, monkeypatch):
    blocks = python_blocks(SOURCE_DIR / "docs" / "python.md")
    assert len(blocks) >= 6
    run_blocks(blocks, tmp_path, monkeypatch)
    written = sorted(p.name for p in (tmp_path / "repo" / "out").iterdir())
    # The cancelled bake left nothing; the in-memory matcaps and IBL wrote only what was saved.
    assert written == ["fit.json", "gold.png", "ibl", "phong.exr", "sky_phong20.exr"]
    assert sorted(p.name for p in (tmp_path / "repo" / "out" / "ibl").iterdir()) == [
        "sky_dfg.ktx2", "sky_ggx.ktx2", "sky_irradiance.ktx2", "sky_sh.json", "sky_skybox.ktx2"]


@pytest.mark.parametrize("matplotlib", [False, True])
def test_the_python_example_of_readme_runs(tmp_path, monkeypatch, cornell, capsys, matplotlib):
    blocks = python_blocks(SOURCE_DIR / "README.md", after="## Python")
    assert len(blocks) == 1 and len(blocks[0].splitlines()) <= 16
    plotted = {}
    if matplotlib:  # a stand-in recording the plot (matplotlib itself need not be installed)
        pyplot = types.ModuleType("matplotlib.pyplot")
        pyplot.plot = lambda x, y, style: plotted.update(x=x, y=y)
        pyplot.savefig = lambda path: plotted.update(path=path)
        package = types.ModuleType("matplotlib")
        package.pyplot = pyplot
        monkeypatch.setitem(sys.modules, "matplotlib", package)
        monkeypatch.setitem(sys.modules, "matplotlib.pyplot", pyplot)
    else:
        monkeypatch.setitem(sys.modules, "matplotlib", None)  # import raises ImportError
        monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    run_blocks(blocks, tmp_path, monkeypatch)
    assert (tmp_path / "repo" / "out" / "garnet.exr").exists()
    if matplotlib:
        # The held-out elevations of a Cornell table: 20 to 70 degrees, each better than Lambert.
        assert [round(x) for x in plotted["x"]] == [20, 30, 40, 50, 60, 70] and max(plotted["y"]) < 1
        assert plotted["path"] == "out/garnet_held_out.png"
    else:
        assert "matplotlib is not installed" in capsys.readouterr().out


def shell_blocks(path):
    """The ```sh blocks of a markdown file that call the built tool (build/cli/brdfbake)."""
    blocks = re.findall(r"^```(?:sh|bash)\n(.*?)^```", path.read_text(), flags=re.S | re.M)
    return [b for b in blocks if "build/cli/brdfbake" in b and "quickstart.sh" not in b and "build/bench" not in b]


def test_every_command_line_of_readme_runs_as_written_after_the_demo(tmp_path, cli, cornell):
    # The demo (scripts/quickstart.sh demo) bakes phong_eye.json into out/; then each block runs in
    # one shell, from a copy of the layout a user has: build/cli/brdfbake, data_samples/, ../shared.
    repo = tmp_path / "repo"
    (repo / "build" / "cli").mkdir(parents=True)
    os.symlink(cli, repo / "build" / "cli" / "brdfbake")
    os.symlink(SOURCE_DIR / "data_samples", repo / "data_samples")
    os.symlink(SHARED_DIR, tmp_path / "shared")
    blocks = shell_blocks(SOURCE_DIR / "README.md")
    assert len(blocks) >= 2 and sum(b.count("build/cli/brdfbake ") for b in blocks) >= 15
    demo = "build/cli/brdfbake bake data_samples/specs/phong_eye.json --out-dir out --quiet\n"
    for i, block in enumerate([demo] + blocks):
        done = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", block], cwd=repo, capture_output=True, text=True)
        assert done.returncode == 0, f"README block {i}:\n{block}\nexit {done.returncode}: {done.stderr[-2000:]}"
    for made in ["out/phong_cube.exr", "out/fit.json", "out/sky.exr", "out/garnet.exr", "teapot.png", "chart.csv"]:
        assert (repo / made).stat().st_size > 0, made
