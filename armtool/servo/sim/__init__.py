"""A simulated servo bus on a pseudo-terminal (Dynamixel 1.0/2.0, Feetech) for tests and demos."""

from armtool.servo.sim.bus import SimBus
from armtool.servo.sim.config import Faults, PersonSpec, SimConfig, load_sim_config, sim_config_from_dict
from armtool.servo.sim.person import Person

__all__ = ["Faults", "Person", "PersonSpec", "SimBus", "SimConfig", "load_sim_config", "sim_config_from_dict"]
