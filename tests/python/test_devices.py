"""kilohertz.haptic's devices from Python: capabilities and readings checked, recorded
trajectories and simulated operators driven by hand."""

import numpy as np
import pytest

import kilohertz
from kilohertz.haptic import (
    Device,
    DeviceCapabilities,
    DeviceState,
    Playback,
    SimulatedOperator,
    TrajectoryDevice,
)


@pytest.mark.bad_input
def test_capabilities_are_validated_with_the_librarys_message():
    caps = DeviceCapabilities(name="pen", max_force=5, max_torque=0.2, max_stiffness=2000)
    assert caps.name == "pen" and caps.output_dof == 6
    np.testing.assert_array_equal(caps.workspace_min, [-0.1, -0.1, -0.1])
    with pytest.raises(kilohertz.Error, match="device 'pen': max_force must be finite and > 0"):
        DeviceCapabilities(name="pen", max_force=-1, max_torque=0.2, max_stiffness=2000)
    with pytest.raises(ValueError, match=r"workspace_min: expected shape \(N, 3\) or \(3,\)"):
        DeviceCapabilities(max_force=1, max_torque=1, max_stiffness=1, workspace_min=[0, 0])


@pytest.mark.bad_input
def test_a_reading_holds_a_unit_quaternion_and_optional_velocities():
    state = DeviceState(position=[0.01, 0, 0], orientation=[0, 1, 0, 0], buttons=3, time=0.5)
    np.testing.assert_array_equal(state.orientation, [0, 1, 0, 0])
    assert state.linear_velocity is None and state.valid and state.buttons == 3
    moving = DeviceState(position=[0, 0, 0], linear_velocity=[0.1, 0, 0])
    np.testing.assert_array_equal(moving.linear_velocity, [0.1, 0, 0])
    with pytest.raises(ValueError, match=r"orientation: expected a unit quaternion \(w, x, y, z\)"):
        DeviceState(position=[0, 0, 0], orientation=[2, 0, 0, 0])
    with pytest.raises(ValueError, match="position: row 0 is not finite"):
        DeviceState(position=[np.nan, 0, 0])


def test_a_trajectory_file_replays_and_records_what_is_written(scene_examples):
    device = TrajectoryDevice(scene_examples / "dragon_press.csv")
    device.open()
    first, second = device.read(), device.read()
    assert second.time > first.time
    assert device.write([1.0, 0, 0], [0, 0, 0.01])
    times, forces, torques = device.recorded
    np.testing.assert_array_equal(forces, [[1.0, 0, 0]])
    np.testing.assert_array_equal(torques, [[0, 0, 0.01]])
    assert times[0] == second.time


def test_a_trajectory_from_arrays_plays_at_the_nominal_rate():
    device = TrajectoryDevice(times=[0.0, 0.01], positions=[[0, 0, 0], [0.01, 0, 0]],
                              playback=Playback.at_nominal_rate)
    device.open()
    readings = [device.read() for _ in range(12)]
    assert readings[5].position[0] == pytest.approx(0.005)
    assert device.finished


@pytest.mark.bad_input
@pytest.mark.parametrize("name", ["empty", "missing_field", "nan_coordinate", "non_numeric",
                                  "non_unit_quaternion", "time_not_increasing", "wrong_header"])
def test_malformed_trajectories_raise_parse_errors_naming_the_file(test_data, name):
    file = test_data / "malformed" / "trajectory" / f"{name}.csv"
    with pytest.raises(kilohertz.ParseError, match=f"{name}.csv"):
        TrajectoryDevice(file)


@pytest.mark.bad_input
def test_bad_trajectory_arrays_are_refused():
    with pytest.raises(ValueError, match=r"positions: expected shape \(2, 3\)"):
        TrajectoryDevice(times=[0, 1], positions=np.zeros((3, 3)))
    with pytest.raises(kilohertz.Error):
        TrajectoryDevice(times=[1, 0], positions=np.zeros((2, 3)))


def test_a_simulated_operator_follows_its_keyframes_against_the_written_force():
    operator = SimulatedOperator(times=[0.0, 0.5], positions=[[0, 0, 0], [0.01, 0, 0]])
    operator.open()
    for _ in range(500):
        operator.read()
    free = operator.position[0]
    operator.open()
    for _ in range(500):
        operator.read()
        operator.write([-2.0, 0, 0])  # pushed back
    assert 0 < operator.position[0] < free
    np.testing.assert_array_equal(operator.applied_force, [-2.0, 0, 0])


def test_the_base_class_reads_nothing_until_a_subclass_defines_read():
    class Silent(Device):
        pass

    silent = Silent(DeviceCapabilities(max_force=1, max_torque=1, max_stiffness=1))
    silent.open()
    assert silent.is_open and silent.read() is None


def test_virtual_coupling_follows_the_hand_within_its_speed_limit():
    from kilohertz.haptic import CouplingOptions, VirtualCoupling

    coupling = VirtualCoupling(CouplingOptions(stiffness=500, max_speed=0.1, period=1e-3))
    step = coupling.step([0.01, 0.0, 0.0])  # 10 mm away, no contact
    assert step["valid"] and step["speed_limited"]
    assert step["simulation_position"][0] == pytest.approx(0.1 * 1e-3)
    # What the device renders pulls the hand back toward the simulation object.
    assert step["rendered_force"][0] < 0
    for _ in range(200):
        step = coupling.step([0.01, 0.0, 0.0])
    np.testing.assert_allclose(coupling.simulation_position, [0.01, 0, 0], atol=1e-9)
    with pytest.raises(kilohertz.Error, match="stiffness"):
        CouplingOptions(stiffness=-1)
