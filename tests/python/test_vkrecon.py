"""`import vkrecon` against the command line: the same numbers, the same errors."""

import json
import os
import subprocess

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
    assert scores["total"][0] == scores["log_likelihood"][0] + scores["log_occlusion_prior"][0]
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
