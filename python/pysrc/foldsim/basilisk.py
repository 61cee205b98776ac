"""A foldsim structure as the spacecraft of a Basilisk simulation (docs/interop.md).

:class:`FoldsimSpacecraft` is a Basilisk ``SysModel`` written in Python (Basilisk's own
pattern for Python modules): each time its task runs it integrates the foldsim run from
the time it reached to Basilisk's time, with the actuator commands it last read held
constant, then publishes the hub's state in Basilisk's standard messages. Basilisk's flight
software (``inertial3D`` → ``attTrackingError`` → ``mrpFeedback`` → ``rwMotorTorque``, or
any other) then flies the deploying structure as it would fly Basilisk's own spacecraft.

Messages out (written at every update, and at ``Reset``):

- ``scStateOutMsg`` (``SCStatesMsg``): the hub's position ``r_BN_N`` and velocity
  ``v_BN_N`` (its centre of mass, N frame), the barycenter's ``r_CN_N`` and ``v_CN_N``,
  ``sigma_BN`` (MRPs, |σ| ≤ 1), ``omega_BN_B``; ``omegaDot_BN_B`` and the accumulated ΔV
  fields are left zero;
- ``attOutMsg`` (``NavAttMsg``): ``sigma_BN``, ``omega_BN_B``, ``timeTag`` (s): what
  ``simpleNav`` gives without noise;
- ``rwSpeedOutMsg`` (``RWSpeedMsg``): each wheel's speed relative to the hub (rad/s), in
  the scenario's ``[[control.wheel]]`` order;
- ``scMassOutMsg`` (``SCMassPropsMsg``): the whole structure's mass, barycenter ``c_B`` and
  inertia about the hub's centre of mass ``ISC_PntB_B`` as it deploys (wheels included);
- ``vehConfigOutMsg`` (``VehicleConfigMsg``): the same mass and inertia, for
  ``mrpFeedback``'s ``vehConfigInMsg`` if a deployment-aware controller is wanted.

Messages in (read at each update; a message never written leaves the structure free):

- ``rwMotorTorqueInMsg`` (``ArrayMotorTorqueMsg``): the wheels' motor torques (N·m), the
  first as many as the scenario has wheels, replacing the scenario's ``[control]`` law
  (the wheels' ``max_torque`` still applies, as Basilisk's ``u_max`` does);
- ``cmdTorqueInMsg`` (``CmdTorqueBodyMsg``): a torque on the hub (N·m, hub frame), as an
  ideal external torque.

Timing: commands written at Basilisk time t act from t on (a zero-order hold). Give the
module's task a higher priority than the flight software's (or the same task and a higher
module priority), so that at each instant the module publishes the state before the flight
software reads it, as Basilisk's own dynamics task does.

Needs Basilisk: ``pip install "./python[basilisk]"`` (the ``bsk`` wheel from PyPI).
"""

from __future__ import annotations

import math

import numpy as np

try:
    from Basilisk.architecture import messaging, sysModel
except ImportError as e:  # pragma: no cover - the message is the point
    raise ImportError(
        "foldsim.basilisk needs Basilisk: pip install \"./python[basilisk]\" (the bsk wheel from PyPI)"
    ) from e

import foldsim

NANO = 1e-9


def _mrp(q) -> list[float]:
    """MRPs σ = q_v / (1 + q_w) of a quaternion (scalar first), the short way round
    (|σ| ≤ 1, Schaub & Junkins eq. 3.137 with the shadow set where q_w < 0)."""
    w, x, y, z = q
    if w < 0.0:
        w, x, y, z = -w, -x, -y, -z
    return [x / (1.0 + w), y / (1.0 + w), z / (1.0 + w)]


def _dcm_n_b(q) -> np.ndarray:
    """[N B] of a quaternion β_{B/N} (scalar first; Schaub & Junkins eq. 3.98 transposed)."""
    w, x, y, z = q
    return np.array(
        [
            [w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z],
        ]
    )


class FoldsimSpacecraft(sysModel.SysModel):
    """A foldsim scenario as a Basilisk spacecraft (see the module's text).

    ``scenario`` is a :class:`foldsim.Scenario` (``foldsim.load(path)``, ``foldsim.from_toml``)
    whose ``run.duration`` covers the Basilisk simulation. The run starts at ``Reset`` (at
    Basilisk's ``InitializeSimulation``), from the scenario's initial state; each
    ``Reset`` starts it again. ``keep_rows``: keep the run's output rows at the scenario's
    output times (``module.simulation.result()``); by default none are kept, so a long
    Basilisk run's memory stays flat (record Basilisk's messages instead).
    """

    def __init__(self, scenario: "foldsim.Scenario", keep_rows: bool = False):
        super().__init__()
        if not isinstance(scenario, foldsim.Scenario):
            raise TypeError(f"FoldsimSpacecraft takes a foldsim.Scenario, got {type(scenario).__name__}")
        self.ModelTag = "foldsim"
        self.scenario = scenario
        self.keep_rows = keep_rows
        self.scStateOutMsg = messaging.SCStatesMsg()
        self.attOutMsg = messaging.NavAttMsg()
        self.rwSpeedOutMsg = messaging.RWSpeedMsg()
        self.scMassOutMsg = messaging.SCMassPropsMsg()
        self.vehConfigOutMsg = messaging.VehicleConfigMsg()
        self.rwMotorTorqueInMsg = messaging.ArrayMotorTorqueMsgReader()
        self.cmdTorqueInMsg = messaging.CmdTorqueBodyMsgReader()
        #: The stepped run (:class:`foldsim.Simulation`), from ``Reset`` on.
        self.simulation = None
        self._start_nanos = 0
        self._wheels: list[str] = []
        self._hub = ""

    def Reset(self, CurrentSimNanos):
        self.simulation = self.scenario.start()
        if not self.keep_rows:
            self.simulation.discard_rows()
        self._start_nanos = CurrentSimNanos
        state = self.simulation.state
        self._hub = self._hub_name(state)
        self._wheels = sorted(
            (n[: -len("_speed")] for n in state if n.endswith("_speed")),
            key=lambda n: list(state).index(n + "_speed"),
        )
        self._publish(CurrentSimNanos)

    def UpdateState(self, CurrentSimNanos):
        if self.simulation is None:
            self.Reset(CurrentSimNanos)
            return
        t = (CurrentSimNanos - self._start_nanos) * NANO
        dt = t - self.simulation.t
        if dt > 1e-12:
            self._read_commands()
            self.simulation.advance(dt)
        self._publish(CurrentSimNanos)

    def _read_commands(self):
        if self.rwMotorTorqueInMsg.isLinked() and self.rwMotorTorqueInMsg.isWritten():
            if not self._wheels:
                raise ValueError(
                    "rwMotorTorqueInMsg is connected but the scenario has no [[control.wheel]]: give it wheels, or leave the message unconnected"
                )
            u = list(self.rwMotorTorqueInMsg().motorTorque)[: len(self._wheels)]
            bad = [x for x in u if not math.isfinite(x)]
            if bad:
                raise ValueError(f"rwMotorTorqueInMsg: wheel torques must be finite numbers, got {bad[0]}")
            self.simulation.set_wheel_torque(u)
        if self.cmdTorqueInMsg.isLinked() and self.cmdTorqueInMsg.isWritten():
            tau = list(self.cmdTorqueInMsg().torqueRequestBody)
            bad = [x for x in tau if not math.isfinite(x)]
            if bad:
                raise ValueError(f"cmdTorqueInMsg: the torque must be finite numbers, got {bad[0]}")
            self.simulation.set_torque(self._hub, tau, frame="body")

    def _publish(self, nanos):
        s = self.simulation.state
        q = [s["q_B_w"], s["q_B_x"], s["q_B_y"], s["q_B_z"]]
        sigma = _mrp(q)
        omega = [s["w_B_x"], s["w_B_y"], s["w_B_z"]]
        hub = self._hub
        r_b = [s["R_B_x"], s["R_B_y"], s["R_B_z"]]
        v_b = [s[f"{hub}_v_x"], s[f"{hub}_v_y"], s[f"{hub}_v_z"]]
        mass, c_b, inertia = self.simulation.mass_properties()
        r_c = [s["Rc_x"], s["Rc_y"], s["Rc_z"]]
        v_c = [s["P_x"] / mass, s["P_y"] / mass, s["P_z"] / mass]

        sc = messaging.SCStatesMsgPayload()
        sc.r_BN_N, sc.v_BN_N, sc.r_CN_N, sc.v_CN_N = r_b, v_b, r_c, v_c
        sc.sigma_BN, sc.omega_BN_B = sigma, omega
        self.scStateOutMsg.write(sc, nanos, self.moduleID)

        att = messaging.NavAttMsgPayload()
        att.timeTag = nanos * NANO
        att.sigma_BN, att.omega_BN_B = sigma, omega
        self.attOutMsg.write(att, nanos, self.moduleID)

        speeds = messaging.RWSpeedMsgPayload()
        speeds.wheelSpeeds = [s[f"{w}_speed"] for w in self._wheels]
        self.rwSpeedOutMsg.write(speeds, nanos, self.moduleID)

        props = messaging.SCMassPropsMsgPayload()
        props.massSC, props.c_B, props.ISC_PntB_B = mass, list(c_b), inertia.tolist()
        self.scMassOutMsg.write(props, nanos, self.moduleID)
        config = messaging.VehicleConfigMsgPayload()
        config.massSC, config.CoM_B, config.ISCPntB_B = mass, list(c_b), inertia.flatten().tolist()
        self.vehConfigOutMsg.write(config, nanos, self.moduleID)

    @staticmethod
    def _hub_name(state) -> str:
        # The hub is the first body: the first `<body>_v_*` columns are its (docs/outputs.md).
        for name in state:
            if name.endswith("_v_x") and not name.startswith("R_"):
                return name[: -len("_v_x")]
        raise RuntimeError("the run's state has no body velocity columns")
