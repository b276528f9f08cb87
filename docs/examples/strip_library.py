"""Scripting lcefem from Python (docs/library.md): the thermo-mechanical strip with prescribed
spontaneous-stretch and temperature fields, a custom support, and the Kapton specimen's buckling
load.

Run: ``python docs/examples/strip_library.py [--level L] [--out DIR]`` (level 0: about 10 s on one
core). tests/test_library_example.py runs it at level 0 and checks its numbers.
"""

from __future__ import annotations

import argparse
import pathlib

# Any lcefem.solvers import orders MPI ahead of dolfinx; after it, `import dolfinx` works too.
from lcefem.meshes.kapton_ribbon import KaptonFEMesh, KaptonSpecimenGeometry
from lcefem.meshes.strip import StripMesh
from lcefem.solvers.problems.kapton_specimen import KaptonSpecimenFE
from lcefem.solvers.problems.strip import StripConfig, StripRun, StripSimulation
from lcefem.solvers.supports import clamp_face, mirror_planes


def main(level: int = 0, out: pathlib.Path | None = None) -> dict[str, float]:
    """Returns the numbers the script prints (name [unit] -> value)."""
    results: dict[str, float] = {}

    # 1. A free strip (no current) at a uniform spontaneous stretch: with no load it takes exactly
    #    that length relative to its isotropic length.
    free = StripSimulation(
        StripConfig(run=StripRun(bc="free", current=0.0), mesh=StripMesh(level=level))
    )
    free.set_spontaneous_stretch(1.2)
    results["free strip stretch at lambda_s = 1.2 [-]"] = free.observables()["stretch [-]"]

    # 2. The same strip with the coil cells at 90 C and the rest at room temperature (per cell tag),
    #    then a linear stretch field along the strip (a callable of the reference coordinates, mm).
    free.set_temperature({"coil": 90.0, "lce": 25.0})
    results["free strip stretch, coil at 90 C [-]"] = free.observables()["stretch [-]"]
    length = free.dims["length"]
    free.set_spontaneous_stretch(lambda x: 1.35 - 0.1 * x[0] / length)
    results["free strip stretch, graded 1.35 -> 1.25 [-]"] = free.observables()["stretch [-]"]

    # 3. Held strip (both ends clamped at the as-built length): the force of a uniform stretch.
    held = StripSimulation(
        StripConfig(run=StripRun(bc="held", current=0.0), mesh=StripMesh(level=level))
    )
    held.set_spontaneous_stretch(1.2)
    results["held strip force at lambda_s = 1.2 [N]"] = held.observables()["force [N]"]

    # 4. The supports are named helpers, usable on any tagged mesh and displacement space.
    bcs = clamp_face(held.tmesh, held.model.u.function_space, "clamp")
    bcs += mirror_planes(held.tmesh, held.model.u.function_space, [("sym_y", 1), ("sym_z", 2)])
    results["support conditions built [-]"] = float(len(bcs))

    # 5. The Kapton buckling specimen (seed 001 Fig. 2G): critical load of the perfect specimen.
    specimen = KaptonSpecimenFE(KaptonSpecimenGeometry(), KaptonFEMesh(level=level))
    results["Kapton specimen critical load [N]"] = specimen.critical_load().force
    if out is not None:
        specimen.write_fields(out / "kapton")

    for name, value in results.items():
        print(f"{name}: {value:.6g}")
    return results


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", type=int, default=0, help="mesh refinement level (default 0)")
    parser.add_argument("--out", type=pathlib.Path, help="folder for the specimen's field files")
    args = parser.parse_args()
    main(args.level, args.out)
