"""kilohertz.scene.report(): the figures `khz report` writes into report.md, as data. The same
scene is reported by the khz tool and from Python, and every figure that does not depend on the
machine's speed (errors, nodes, stability) must read the same."""

import json
import os
import re
import subprocess

import pytest

import kilohertz
from kilohertz import scene

DURATION = 1.2  # s of example (g): the paddle reaches the block and pushes it


@pytest.fixture(scope="module")
def both(scene_examples, product_cache, tmp_path_factory):
    tool = os.environ.get("KHZ_TOOL_PATH")
    if not tool:
        pytest.fail("KHZ_TOOL_PATH is not set: the khz tool is built with KHZ_BUILD_TOOLS")
    out = tmp_path_factory.mktemp("report")
    source = scene_examples / "block_push.json"
    run = subprocess.run([tool, "report", str(source), "--duration", str(DURATION),
                          "--frames", "0", "--out", str(out)], capture_output=True, text=True,
                         env={**os.environ, "XDG_CACHE_HOME": str(product_cache.parent)})
    assert run.returncode == 0, run.stderr
    prepared = scene.prepare_scene(scene.read_scene(source), cache_directory=product_cache)
    return (out / "report.md").read_text(), scene.report(prepared, DURATION)


def table_rows(markdown, first_header):
    """The rows of the Markdown table whose header starts with `first_header`, by first cell."""
    lines = markdown.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(f"| {first_header} |"))
    rows = {}
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        cells = [cell.strip() for cell in line.strip("|").split("|")]
        rows[cells[0]] = cells[1:]
    return rows


def number(cell):
    return float(re.match(r"-?[\d.]+", cell).group())


def test_the_sweep_reads_as_khz_report_wrote_it(both):
    markdown, report = both
    tool = table_rows(markdown, "setting | µs mean")
    assert [row["name"] for row in report["sweep"]] == list(tool)
    for row in report["sweep"]:
        if "budget" in row["name"]:
            continue  # a time budget's level of detail follows the measured cost
        nodes, rms, peak, torque = tool[row["name"]][2:6]
        assert round(row["mean_nodes"]) == number(nodes)
        assert f"{100 * row['force_error']:.2f}" == f"{number(rms):.2f}"
        assert f"{100 * row['max_force_error']:.2f}" == f"{number(peak):.2f}"
        assert f"{100 * row['torque_error']:.2f}" == f"{number(torque):.2f}"
    assert report["sweep"][0]["force_error"] == 0.0 and report["sweep"][0]["states"] > 0


def test_the_stability_map_reads_as_khz_report_wrote_it(both):
    markdown, report = both
    tool = table_rows(markdown, "setting | stable")
    assert [row["name"] for row in report["stability"]] == list(tool)
    for row in report["stability"]:
        stable, smooth, jump, rendered, peak = tool[row["name"]][:5]
        assert row["stable"] == (stable == "yes") and row["smooth"] == (smooth == "yes")
        assert f"{row['contact_jump_p99']:.1f}" == f"{number(jump):.1f}"
        assert f"{row['rendered_jump_p99']:.1f}" == f"{number(rendered):.1f}"
        assert row["peak_contact_force"] == pytest.approx(number(peak), rel=5e-3)


def test_the_summary_holds_the_run_and_the_runtimes_metrics(both):
    _, report = both
    summary = report["summary"]
    assert summary["cycles"] == round(DURATION * 1000) and summary["finite"]
    assert summary["max_force"] > 2.4  # the push that breaks the block loose (μ_s m g = 2.45 N)
    assert summary["metrics"]["cycles"] == summary["cycles"]
    assert summary["metrics"]["lowest_energy"] >= -1e-3


@pytest.mark.bad_input
def test_a_report_without_a_duration_is_refused(scene_examples, product_cache):
    prepared = scene.prepare_scene(scene.read_scene(scene_examples / "block_push.json"),
                                   cache_directory=product_cache)
    with pytest.raises(ValueError, match=r"duration: expected 0 \(the scene's own\) or more"):
        scene.report(prepared, -1.0)
    silent = scene.parse_scene(
        {**scene_text(scene_examples), "haptic": [{"object": "paddle", "device": {"type": "null"}}]},
        base_directory=scene_examples)
    with pytest.raises(kilohertz.Error, match="no duration"):
        scene.report(scene.prepare_scene(silent, cache_directory=product_cache))


def scene_text(scene_examples):
    return json.loads((scene_examples / "block_push.json").read_text())
