"""`import vkrecon` against the command line: the same numbers, the same errors."""

import json
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import vkrecon

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HOUSE = os.path.join(ROOT, "assets", "house")
BINARY = os.environ["VKRECON_BINARY"]


@pytest.fixture(scope="module")
def photos(tmp_path_factory):
    """The house photographed at its truth, small (the command line's synth)."""
    out = tmp_path_factory.mktemp("house")
    subprocess.run([BINARY, "synth", os.path.join(HOUSE, "scene.json"), "--at", os.path.join(HOUSE, "truth.json"),
                    "--scale", "0.25", "--noise", "8", "--seed", "1", "-q", "-o", str(out)], check=True)
    return [f"cameras={out}/cameras.json", f"images={out}", "likelihood.atlas=128"]


@pytest.fixture(autouse=True, scope="module")
def no_validation_messages():
    yield
    assert vkrecon.validation_messages() == []


def cli_total(sets, at):
    args = [BINARY, "likelihood", os.path.join(HOUSE, "scene.json"), "--at", at, "-q"]
    for s in sets:
        args += ["--set", s]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return float(next(line.split()[1] for line in out.splitlines() if line.startswith("total ")))


def test_batch_equals_the_command_line_to_the_bit(photos, tmp_path):
    scene = vkrecon.Scene.load(os.path.join(HOUSE, "scene.json"), set=photos)
    truth = scene.values_from_file(os.path.join(HOUSE, "truth.json"))
    moved = truth.copy()
    moved[scene.parameter_names.index("w")] += 0.05
    vkrecon.write_at(scene, tmp_path / "moved.json", moved)

    likelihood = vkrecon.Likelihood(scene, batch=2)
    likelihood.calibrate_photometric(truth)  # what `likelihood --at truth` fits before scoring
    scores = likelihood.evaluate(np.stack([truth, moved, truth]))  # two submissions
    assert scores["total"][0] == cli_total(photos, os.path.join(HOUSE, "truth.json"))
    assert scores["total"][2] == scores["total"][0]
    assert scores["total"][1] < scores["total"][0]
    # The edge term is on by default: the total is its three terms, summed in this order.
    assert scores["log_edges"][0] != 0.0
    assert scores["total"][0] == (scores["log_likelihood"][0] + scores["log_edges"][0]
                                  + scores["log_occlusion_prior"][0])
    assert scores["seen_multi"][0] > 0


def test_levels_are_coarser_and_cheaper(photos):
    scene = vkrecon.Scene.load(os.path.join(HOUSE, "scene.json"), set=photos)
    likelihood = vkrecon.Likelihood(scene, batch=1, level=1)
    assert likelihood.level == 1 and likelihood.levels >= 2 and likelihood.kind == "surface"
    dof = likelihood.evaluate(scene.initial_values[None, :])["dof"][0]
    likelihood.level = 0
    assert likelihood.evaluate(scene.initial_values[None, :])["dof"][0] > dof


def test_at_files_round_trip(tmp_path):
    scene = vkrecon.Scene.load(os.path.join(HOUSE, "scene.json"), require_images=False)
    values = scene.initial_values + 0.01
    vkrecon.write_at(scene, tmp_path / "at.json", values)
    assert json.load(open(tmp_path / "at.json")).keys() == set(scene.parameter_names)
    np.testing.assert_array_equal(vkrecon.read_at(scene, tmp_path / "at.json"), values)


def test_bad_input_raises_the_command_lines_line(tmp_path):
    bad = tmp_path / "scene.json"
    bad.write_text('{"version": 1, "parameters": {"x": {"prior": {"uniform": [1, 0]}}}}')
    with pytest.raises(vkrecon.InputError) as raised:
        vkrecon.Scene.load(bad)
    cli = subprocess.run([BINARY, "likelihood", str(bad), "--at", str(bad)], capture_output=True, text=True)
    assert cli.returncode == 2
    assert cli.stderr.strip() == f"vkrecon likelihood: {raised.value}"


def test_a_dict_is_a_scene(tmp_path):
    scene = json.load(open(os.path.join(HOUSE, "scene.json")))
    loaded = vkrecon.scene_from_dict(scene, base_dir=HOUSE, require_images=False)
    assert loaded.parameter_names == list(scene["parameters"].keys())
    with pytest.raises(ValueError):
        vkrecon.Likelihood(loaded, batch=0)


BOX = os.path.join(ROOT, "assets", "box")
# A short run, as tests/cli/RunCliTest.cpp keeps its runs short: a small atlas, two levels,
# 40 iterations of two chains.
SHORT = ["likelihood.atlas=64", "likelihood.levels=2", "sampler.iterations=40", "sampler.chains=2",
         "sampler.batch=4"]


@pytest.fixture(scope="module")
def box(tmp_path_factory):
    """The box photographed at its truth, quarter size; a short run's settings."""
    out = tmp_path_factory.mktemp("box")
    subprocess.run([BINARY, "synth", os.path.join(BOX, "scene.json"), "--at", os.path.join(BOX, "truth.json"),
                    "--scale", "0.25", "--noise", "8", "--seed", "1", "-q", "-o", str(out)], check=True)
    return [f"cameras={out}/cameras.json", f"images={out}"] + SHORT


@pytest.fixture(scope="module")
def box_run(box, tmp_path_factory):
    """The same short run from Python and from the command line."""
    out = tmp_path_factory.mktemp("runs")
    scene = vkrecon.Scene.load(os.path.join(BOX, "scene.json"), set=box)
    calls = []
    summary = vkrecon.reconstruct(scene, out / "python", progress=lambda n, best: calls.append((n, best)))
    args = [BINARY, "run", "-q", os.path.join(BOX, "scene.json"), "-o", str(out / "cli")]
    for s in box:
        args += ["--set", s]
    subprocess.run(args, check=True, capture_output=True)
    return scene, summary, out, calls


def test_a_run_writes_what_the_command_line_writes(box_run):
    scene, summary, out, _ = box_run
    assert summary.completed and summary.termination == "completed"
    for name in ("map.json", "chain.csv", "at_map.json", "chains/stan-1.csv", "chains/stan-2.csv"):
        assert (out / "python" / name).read_bytes() == (out / "cli" / name).read_bytes(), name
    assert str(out / "python" / "map.json") in [str(p) for p in summary.written]


def test_the_summary_is_map_json(box_run):
    scene, summary, out, _ = box_run
    written = json.load(open(out / "python" / "map.json"))
    assert summary.to_json() == written
    assert [p["name"] for p in summary.parameters] == scene.parameter_names == summary.parameter_names
    for p in summary.parameters:
        for key in ("map", "mean", "sd", "q025", "q975", "ess", "rhat"):
            assert p[key] == written["parameters"][p["name"]][key] or written["parameters"][p["name"]][key] is None
    np.testing.assert_array_equal(summary.map, [written["parameters"][n]["map"] for n in scene.parameter_names])
    assert summary.verdict == written["diagnosis"]["verdict"]
    assert summary.notes == written["diagnosis"]["notes"]
    assert summary.ok == (summary.verdict == "ok")
    assert summary.log_posterior == written["log_posterior"]
    assert "40 iterations" in summary.brief_report() and "\n" not in summary.brief_report()
    assert summary.parameter_names[0] in summary.full_report()


def test_the_map_lies_near_the_truth(box_run):
    scene, summary, _, _ = box_run
    truth = scene.values_from_file(os.path.join(BOX, "truth.json"))
    priors = json.load(open(os.path.join(BOX, "scene.json")))["parameters"]
    width = np.array([np.diff(priors[n]["prior"]["uniform"])[0] for n in scene.parameter_names])
    assert np.all(np.abs(summary.map - truth) < 0.02 * width), (summary.map, truth)


def test_the_draws_are_the_chains_after_burn_in(box_run):
    scene, summary, out, _ = box_run
    written = json.load(open(out / "python" / "map.json"))
    draws, chains = summary.draws, summary.draw_chains
    per_chain = written["iterations"] - written["burn_in"]
    # Once settled, the replicas sample as chains of their own: map.json's posterior_chains.
    n = written["posterior_chains"]
    assert n == 4  # 2 chains of 2 replicas, all four (posterior_chains: 4)
    assert draws.shape == (n * per_chain, len(scene.parameter_names))
    assert list(chains) == [c for c in range(n) for _ in range(per_chain)]
    lines = [line for line in open(out / "python" / "chains" / "stan-1.csv") if not line.startswith("#")]
    header = lines[0].strip().split(",")
    stan = np.array([[float(x) for x in line.split(",")] for line in lines[1:]])
    columns = [header.index(name) for name in scene.parameter_names]
    np.testing.assert_allclose(stan[:, columns], draws[:per_chain], rtol=1e-12)


def test_a_view_is_what_render_writes(box, box_run, tmp_path):
    scene, summary, out, _ = box_run
    texture = out / "python" / "composite.exr"
    view = vkrecon.render(scene, at=summary.map, camera="cam1", texture=texture, scale=0.5)
    vkrecon.write_at(scene, tmp_path / "map.json", summary.map)
    args = [BINARY, "render", "-q", os.path.join(BOX, "scene.json"), "--at", str(tmp_path / "map.json"),
            "--camera", "cam1", "--texture", str(texture), "--scale", "0.5", "-o", str(tmp_path / "cam1.exr")]
    for s in box:
        args += ["--set", s]
    subprocess.run(args, check=True)
    written = vkrecon.load_image(tmp_path / "cam1.exr")
    assert view.shape == written.shape and view.shape[2] == 4 and view.dtype == np.float32
    np.testing.assert_array_equal(view, written)
    assert 0 < view[:, :, 3].mean() < 1  # the box and its ground, and the sky beyond
    with pytest.raises(vkrecon.InputError):
        vkrecon.render(scene, camera="no such camera")


def test_a_run_that_cannot_start_raises_the_command_lines_line(box, tmp_path):
    away = box + ['nodes[0].transforms=[{"translate": [100, 0, 0]}, {"scale": [5, 5, 1]}]',
                  'nodes[1].transforms=[{"translate": ["x+100", "y", 0]}, {"rotate": [0, 0, "yaw"]}, '
                  '{"scale": ["w", "d", "h"]}]']
    scene = vkrecon.Scene.load(os.path.join(BOX, "scene.json"), set=away)
    with pytest.raises(vkrecon.InputError) as raised:
        vkrecon.reconstruct(scene, tmp_path / "python")
    args = [BINARY, "run", "-q", os.path.join(BOX, "scene.json"), "-o", str(tmp_path / "cli")]
    for s in away:
        args += ["--set", s]
    cli = subprocess.run(args, capture_output=True, text=True)
    assert cli.returncode == 2
    assert cli.stderr.strip() == f"vkrecon run: {raised.value}"


def test_progress_follows_the_run(box_run):
    scene, summary, _, calls = box_run
    assert len(calls) >= 40  # one a frame at least: 40 iterations
    counts = [n for n, _ in calls]
    assert counts == sorted(counts) and counts[-1] > counts[0] > 0
    assert all(len(best) == len(summary.parameters) for _, best in calls)


def test_an_exception_in_progress_checkpoints_the_run_and_is_raised(box, tmp_path):
    scene = vkrecon.Scene.load(os.path.join(BOX, "scene.json"), set=box + ["sampler.iterations=400"])
    out = tmp_path / "run"

    def stop(evaluations, best):
        if (out / "checkpoint.json").exists():
            raise ValueError("enough")

    with pytest.raises(ValueError, match="enough"):
        vkrecon.reconstruct(scene, out, checkpoint_seconds=0.05, progress=stop)
    assert (out / "checkpoint.json").exists() and not (out / "map.json").exists()


def test_ctrl_c_checkpoints_the_run_and_raises(box, tmp_path):
    scene = vkrecon.Scene.load(os.path.join(BOX, "scene.json"), set=box + ["sampler.iterations=400"])
    out = tmp_path / "run"

    def interrupt():  # once the run has a checkpoint to continue from
        while not (out / "checkpoint.json").exists():
            time.sleep(0.05)
        os.kill(os.getpid(), signal.SIGINT)

    thread = threading.Thread(target=interrupt)
    thread.start()
    with pytest.raises(KeyboardInterrupt):
        vkrecon.reconstruct(scene, out, checkpoint_seconds=0.05)
    thread.join()
    assert (out / "checkpoint.json").exists() and not (out / "map.json").exists()
