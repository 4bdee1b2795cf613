"""vkrecon from Python: scenes, the likelihood on a numpy batch, the --at format, whole runs
and rendered views.

    import numpy as np, vkrecon
    scene = vkrecon.Scene.load("assets/house/scene.json", set=["images=out/house/images"])
    at = scene.values_from_file("assets/house/truth.json")
    likelihood = vkrecon.Likelihood(scene, batch=16)
    likelihood.calibrate_photometric(at)            # as `vkrecon likelihood --at` does
    scores = likelihood.evaluate(np.stack([at, scene.initial_values]))
    print(scores["total"])

    run = vkrecon.reconstruct(scene, "out/house/run")   # `vkrecon run`: map.json and the rest
    print(run.brief_report(), run.parameters[0], run.draws.shape)
    view = vkrecon.render(scene, at=run.map, texture="out/house/run/composite.exr")

docs/guide/PYTHON.md has more. Bad input raises vkrecon.InputError (a ValueError) carrying
the one line the command line prints.
"""

import json
import os
import tempfile

from ._vkrecon import (InputError, Likelihood, ReconstructSummary, Scene, load_image, reconstruct, render,
                       validation_messages)

__all__ = ["InputError", "Likelihood", "ReconstructSummary", "Scene", "load_image", "reconstruct", "render",
           "validation_messages", "scene_from_dict", "read_at", "write_at"]


def scene_from_dict(scene, base_dir=".", set=(), require_images=True):
    """A scene from a dict in the scene file's format; relative paths resolve from base_dir."""
    fd, path = tempfile.mkstemp(suffix=".json", prefix=".vkrecon_scene_", dir=base_dir)
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(scene, f)
        return Scene.load(path, list(set), require_images)
    finally:
        os.remove(path)


def read_at(scene, path):
    """An --at file's values, in the order of scene.parameter_names (a numpy array)."""
    return scene.values_from_file(path)


def write_at(scene, path, values):
    """Writes values (in the order of scene.parameter_names) as an --at file."""
    scene.write_values(path, values)
