"""The machine under load: what the inverse dynamics costs per cycle position, beside the kinematics.

Seed 004's train (``parts/planetary_seed004.py``'s machine: the designed motion, 3 planets) with
the masses its build records (ring 5.90 kg, carrier 6.32 kg, each planet link 0.54 kg with its arm
and needle — the lumps here are those links' totals, placed where the build finds them), its ten
supports and three meshes, and a needle force at each tip. Times, in the same run:

* **kinematics**: every link's pose at N positions (what the motion table and the judge pose);
* **kinematics with rates**: the poses and their five-point derivatives (velocity, acceleration)
  the dynamics starts from;
* **dynamics**: :func:`transplanter.machine.dynamics.solve` — Newton-Euler, virtual power, the
  supports' shares, the shaking force.

and prints each per position and the dynamics' cost as a multiple of the kinematics'.

Run: python benchmarks/dynamics.py [positions]
"""

import math
import sys
import time
from pathlib import Path

import numpy as np

from transplanter.families import load_family
from transplanter.machine.bodies import PlanetaryMachine
from transplanter.machine.dynamics import Drive, Machine, Mesh, Pin, PointLoad, link_motion, solve
from transplanter.machine.mass import Lump

ROOT = Path(__file__).resolve().parents[1]


def model(study) -> Machine:
    tr = study.train
    links = PlanetaryMachine(tr).links
    lumps = {
        "ring": (Lump(5.90, (0.0, 0.0, -20.9), 69_661.0),),
        "carrier": (Lump(6.32, (0.0, 0.0, -0.3), 29_501.0),),
    }
    pins = [Pin("ring", "fixed", "ring", (-94.65, -45.35)), Pin("carrier", "ring", "carrier", (-129.55, -22.2))]
    meshes, loads = [], []
    for k in range(1, tr.planets + 1):
        lumps[f"planet.{k}"] = (Lump(0.54, (29.3, 1.4, 18.7), 709.0),)
        pins.append(Pin(f"planet {k}", "carrier", f"planet.{k}", (-8.1, 20.1)))
        meshes.append(Mesh(f"mesh {k}", "ring", f"planet.{k}", 6.0, ring="a"))
        loads.append(PointLoad(f"tip {k}", f"planet.{k}", tuple(study.arm.tip), 40.0, _against(100.0)))
    drives = (Drive("ring motor", "ring"), Drive("carrier motor", "carrier"))
    return Machine(links, lumps, tuple(pins), tuple(meshes), drives, tuple(loads))


def _against(force):
    def f(theta, pos, vel):
        speed = np.linalg.norm(vel, axis=1)[:, None]
        return -force * vel / np.maximum(speed, 1e-12) * (pos[:, 1:2] < -170.0)

    return f


def best(fn, repeat=5) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main(n: int = 360) -> None:
    family = load_family(ROOT / "parts" / "planetary_seed004.py")
    study = next(p for p in family.parts if p.name == "machine")
    m = model(study)
    theta = 2 * math.pi * np.arange(n) / n
    speed = study.train.carrier_speed

    def poses():
        for link in m.links.values():
            link.pose(theta)

    def rates():
        for name in m.moving:
            link_motion(m.links[name], theta, speed)

    loads = solve(m, theta, speed)
    t_pose, t_rates, t_dyn = best(poses), best(rates), best(lambda: solve(m, theta, speed))
    per = 1e6 / n
    print(
        f"seed 004's machine, {n} positions, {len(m.moving)} moving links, {len(m.pins)} pins, {len(m.meshes)} meshes"
    )
    print(f"  kinematics (poses)               {t_pose * per:9.1f} us per position")
    print(f"  kinematics with rates            {t_rates * per:9.1f} us per position")
    print(f"  dynamics (NE + VP + supports)    {t_dyn * per:9.1f} us per position")
    print(f"  dynamics / kinematics            {t_dyn / t_pose:9.1f} x   (/ with rates: {t_dyn / t_rates:.1f} x)")
    print(f"  Newton-Euler vs virtual power    {loads.power_error:.2e} of the largest drive power")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 360)
