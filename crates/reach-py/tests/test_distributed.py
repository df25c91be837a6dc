"""reach.distributed on a local Ray with 2 workers gives the same map as one process."""

import numpy as np
import pytest

import reach
from reach import distributed

ray = pytest.importorskip("ray")


@pytest.fixture(scope="module")
def local_ray():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield
    ray.shutdown()


def test_workspace_map_on_two_workers_equals_one_process(local_ray):
    ur5 = reach.Robot.preset("ur5")
    axis = np.linspace(-0.9, 0.9, 15)
    one = distributed.workspace_map(ur5, axis, axis, axis, workers=0)
    two = distributed.workspace_map(ur5, axis, axis, axis, chunk=500, workers=2)
    for key in one:
        np.testing.assert_array_equal(one[key], two[key])
    assert one["reachable"].any() and not one["reachable"].all()


def test_ik_dataset_on_ray_equals_one_process(local_ray):
    puma = reach.Robot.preset("puma560")
    q = np.random.default_rng(5).uniform(-np.pi, np.pi, (2000, 6))
    one = distributed.ik_dataset(puma, q, workers=0)
    two = distributed.ik_dataset(puma, q, chunk=300, workers=2)
    np.testing.assert_array_equal(one["q"], two["q"])
    np.testing.assert_array_equal(one["valid"], two["valid"])
    assert one["branch"] == two["branch"]


def test_the_ray_example_runs_and_agrees(capsys):
    import importlib.util
    import pathlib

    if ray.is_initialized():
        ray.shutdown()
    path = pathlib.Path(__file__).resolve().parents[1] / "examples" / "ray_workspace_map.py"
    spec = importlib.util.spec_from_file_location("ray_workspace_map", path)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    assert example.main(["--points", "11", "--workers", "2", "--chunk", "300"]) == 0
    assert "maps equal: True" in capsys.readouterr().out
