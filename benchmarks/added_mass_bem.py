"""Re-computation of the added-mass table of ``mineburial/kernels/mine/added_mass.py`` with the
boundary-element package capytaine (https://github.com/capytaine/capytaine; NOT a project
dependency: run it in a separate environment, ``pip install capytaine``).

Closed circular cylinder (flat ends) of radius 1 in unbounded fluid (no free surface:
``free_surface = inf``, Rankine Green function only, frequency-independent), rho = 1.
Prints, per L/D, the surge (axial) and sway (transverse) added masses as fractions of rho V
and the pitch added moment of inertia as a fraction of strip theory's rho pi R^2 L^3 / 12;
first a sphere, whose exact coefficient is 0.5, as a check of the mesh resolution
(0.4993 at 1152 panels, 0.4999 at 2592 with the direct method; the indirect one gives 0.517, 0.512).

    python benchmarks/added_mass_bem.py
"""

import math

import capytaine as cpt
import numpy as np

RHO = 1.0


def coefficients(mesh, volume, rot_ref=None):
    body = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0)))
    solver = cpt.BEMSolver(method="direct")  # converges faster than the indirect method on the sphere
    out = {}
    for dof in ("Surge", "Sway", "Pitch"):
        pb = cpt.RadiationProblem(
            body=body, free_surface=np.inf, water_depth=np.inf, omega=1.0, rho=RHO, radiating_dof=dof
        )
        res = solver.solve(pb, keep_details=False)
        out[dof] = res.added_masses[dof]
    return out["Surge"] / (RHO * volume), out["Sway"] / (RHO * volume), out["Pitch"]


def main():
    sphere = cpt.mesh_sphere(radius=1.0, resolution=(36, 72))
    ka, kt, _ = coefficients(sphere, 4.0 / 3.0 * math.pi)
    print(f"sphere: surge {ka:.4f}, sway {kt:.4f} (exact 0.5)")
    print("L/D   k_axial  k_transverse  k_t-k_a  pitch/(rho pi R^2 L^3/12)")
    for ld in (2.0, 3.0, 4.0, 6.0):
        length = 2.0 * ld
        nx = int(round(8 * ld))
        mesh = cpt.mesh_horizontal_cylinder(
            length=length, radius=1.0, center=(0, 0, 0), resolution=(8, 40, nx)
        )
        volume = math.pi * length
        ka, kt, pitch = coefficients(mesh, volume)
        strip = RHO * math.pi * length**3 / 12.0
        print(f"{ld:4.1f}  {ka:7.4f}  {kt:12.4f}  {kt - ka:7.4f}  {pitch / strip:.4f}")


if __name__ == "__main__":
    main()
