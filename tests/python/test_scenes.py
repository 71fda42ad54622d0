"""kilohertz.scene from Python: scenes read, prepared through the cache and run, equal to the same
run in C++; devices written in Python in the haptic cycle; errors and Ctrl-C."""

import json
import os
import signal
import threading

import numpy as np
import pytest

import kilohertz
from kilohertz import scene
from kilohertz.haptic import Device, DeviceCapabilities, DeviceState

CYCLES = 1500  # the block_push paddle reaches the block and pushes it from cycle ~1000


@pytest.fixture(scope="module")
def block_push(scene_examples, product_cache):
    description = scene.read_scene(scene_examples / "block_push.json")
    return scene.prepare_scene(description, cache_directory=product_cache)


def test_every_bundled_scene_reads(scene_examples):
    for file in sorted(scene_examples.glob("*.json")):
        description = scene.read_scene(file)
        assert description.object_names and description.hand_count >= 1, file


@pytest.mark.bad_input
def test_a_scene_from_a_dict_is_validated_with_key_paths(scene_examples):
    text = json.loads((scene_examples / "block_push.json").read_text())
    parsed = scene.parse_scene(text, base_directory=scene_examples)
    assert parsed.object_names == ["table", "block", "paddle"]
    text["contact"]["stifness"] = 1000
    with pytest.raises(scene.SceneError, match=r"contact.*stifness.*stiffness"):
        scene.parse_scene(text, source="mine.json")
    with pytest.raises(scene.SceneError, match=r"mine.json:1:"):
        scene.parse_scene("{ not json", source="mine.json")
    assert issubclass(scene.SceneError, kilohertz.Error)


def test_preparation_reports_progress_and_a_second_one_computes_nothing(scene_examples,
                                                                        tmp_path):
    description = scene.read_scene(scene_examples / "block_push.json")
    stages = []
    first = scene.prepare_scene(description, cache_directory=tmp_path,
                                progress=lambda stage, done, total: stages.append(stage))
    assert first.computed > 0 and not first.warnings
    assert any(stage.startswith("block: ") for stage in stages)
    again = scene.prepare_scene(description, cache_directory=tmp_path)
    assert again.computed == 0
    assert {row["origin"] for row in again.records} <= {"read", "built"}
    with pytest.raises(kilohertz.Cancelled):
        scene.prepare_scene(description, cache_directory=tmp_path / "other",
                            progress=lambda stage, done, total: False)


def test_a_run_equals_the_same_run_in_cpp_bit_for_bit(scene_examples, product_cache, reference,
                                                       block_push, tmp_path):
    rows = scene.SceneRuntime(block_push).run(cycles=CYCLES)[0]
    reference("scene", scene_examples / "block_push.json", product_cache, CYCLES,
              tmp_path / "cpp")
    cpp = np.fromfile(tmp_path / "cpp").reshape(-1, 6)
    np.testing.assert_array_equal(rows["contact_force"], cpp[:, :3])
    np.testing.assert_array_equal(rows["simulation_position"], cpp[:, 3:])
    assert np.abs(rows["contact_force"]).max() > 0.5  # the paddle did push the block


def test_run_records_and_metrics_agree(block_push):
    runtime = scene.SceneRuntime(block_push)
    rows = runtime.run(cycles=CYCLES)[0]
    assert rows["time"].shape == (CYCLES,) and rows["contact_force"].shape == (CYCLES, 3)
    assert rows["device_valid"].dtype == bool and rows["device_valid"].all()
    metrics = runtime.metrics(0)
    assert metrics["cycles"] == CYCLES
    peak = np.linalg.norm(rows["contact_force"], axis=1).max()
    assert metrics["peak_contact_force"] == pytest.approx(peak, rel=1e-12)
    np.testing.assert_allclose(np.linalg.norm(runtime.pose(1)[:3, :3], axis=0), 1.0)
    assert runtime.coordinates(1).shape == (0,)  # rigid
    with pytest.raises(IndexError, match="object 7 out of range"):
        runtime.pose(7)


class Relay(Device):
    """A device written in Python that passes every call on to another device."""

    def __init__(self, inner):
        super().__init__(inner.capabilities)
        self.inner = inner
        self.reads = 0

    def open(self):
        self.inner.open()

    def close(self):
        self.inner.close()

    def read(self):
        self.reads += 1
        return self.inner.read()

    def write(self, force, torque):
        return self.inner.write(force, torque)


def test_a_python_device_in_the_cycle_gives_the_cpp_devices_result(block_push):
    operator = {"type": "operator",
                "keyframes": [{"time": 0.0, "position": [0.0, 0.0, 0.0]},
                              {"time": 0.3, "position": [0.0, 0.0, 0.0]},
                              {"time": 3.3, "position": [0.06, 0.0, 0.0]}],
                "hand": {"stiffness": 1000, "damping": 30}}
    direct = scene.make_device(operator)
    relay = Relay(scene.make_device(operator))
    expected = scene.SceneRuntime(block_push, [direct]).run(cycles=CYCLES)[0]
    through_python = scene.SceneRuntime(block_push, [relay]).run(cycles=CYCLES)[0]
    assert relay.reads == CYCLES
    for column in ("contact_force", "simulation_position", "rendered_force", "observed_energy"):
        np.testing.assert_array_equal(through_python[column], expected[column])


@pytest.mark.bad_input
def test_an_exception_in_a_python_device_stops_the_run_and_is_raised(block_push):
    class Failing(Relay):
        def read(self):
            if self.reads == 100:
                raise ValueError("sensor unplugged")
            return super().read()

    failing = Failing(scene.make_device({"type": "null"}))
    with pytest.raises(ValueError, match="sensor unplugged"):
        scene.SceneRuntime(block_push, [failing]).run(cycles=CYCLES)
    assert failing.reads == 100 and not failing.is_open

    class Garbage(Relay):
        def read(self):
            return "not a reading"

    with pytest.raises(TypeError, match="must return a DeviceState or None"):
        scene.SceneRuntime(block_push, [Garbage(scene.make_device({"type": "null"}))]).run(
            cycles=10)


@pytest.mark.bad_input
def test_runs_without_a_duration_or_with_the_wrong_devices_are_refused(block_push):
    with pytest.raises(ValueError, match="no duration"):
        scene.SceneRuntime(block_push, [scene.make_device({"type": "null"})]).run()
    with pytest.raises(kilohertz.Error, match=r"1 hand\(s\) but 2 device\(s\)"):
        scene.SceneRuntime(block_push, [None, None])
    with pytest.raises(scene.SceneError, match="keyframes"):
        scene.make_device({"type": "operator", "keyframes": []})


def test_ctrl_c_stops_a_run(block_push):
    null = scene.make_device({"type": "null"})
    runtime = scene.SceneRuntime(block_push, [null])
    timer = threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        runtime.run(duration=3600.0)
    timer.join()
    assert not null.is_open


def test_a_loop_driven_from_python_sees_the_world(scene_examples, product_cache):
    prepared = scene.prepare_scene(scene.read_scene(scene_examples / "pick_and_place.json"),
                                   cache_directory=product_cache)
    runtime = scene.SceneRuntime(prepared)
    assert len(runtime.body_names) == len(prepared.description.object_names)
    assert runtime.pairs and all(a != b for a, b in runtime.pairs)
    runtime.open_devices()
    for i in range(50):
        hands = runtime.cycle(i * 1e-3)
    runtime.close_devices()
    assert len(hands) == runtime.hand_count and hands[0]["time"].shape == (1,)
    assert hands[0]["time"][0] == pytest.approx(49e-3)
    result = runtime.pair_result(0)
    assert result.force.shape == (3,)
    with pytest.raises(IndexError, match="pair 99 out of range"):
        runtime.pair_result(99)
    assert runtime.release(0) >= 0 and runtime.grasp(5) == -1
