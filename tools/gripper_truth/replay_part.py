"""The part of replay.py as MuJoCo gets it: an exact convex decomposition of an extruded outline
(`decompose_extrusion`, the Python package's, loaded by path: numpy only; CoACD as the fallback for another
shape) and its mass properties."""
import importlib.util
from pathlib import Path

import numpy as np
import trimesh

_spec = importlib.util.spec_from_file_location(
    "pregrasp_sim_part", Path(__file__).resolve().parents[2] / "python/pregrasp/sim/part.py")
_part = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_part)


def decompose_extrusion(mesh, tol=1e-6):
    """Exact convex decomposition of a prism (a planar outline, holes allowed, extruded along z): the Python
    package's (python/pregrasp/sim/part.py, on the mesh's triangles in face order), with the mesh volume and
    its check from trimesh as before. Returns (list of (k, 3) vertex arrays, info dict); ValueError if the
    mesh is not such a prism."""
    pieces, info = _part.decompose_extrusion(np.asarray(mesh.triangles, float), tol)
    vol = info["pieces_volume"]
    info.update(mesh_volume=float(mesh.volume), volume_rel_error=abs(vol - mesh.volume) / mesh.volume)
    return pieces, info


poly_area = _part.poly_area


def decompose_coacd(mesh, threshold=0.02):
    """Fallback for a part that is not an extrusion: CoACD (pip install coacd)."""
    import coacd
    parts = coacd.run_coacd(coacd.Mesh(mesh.vertices, mesh.faces), threshold=threshold, seed=0)
    pieces = [np.asarray(v) for v, _ in parts]
    vol = sum(trimesh.Trimesh(v).convex_hull.volume for v in pieces)
    return pieces, {"method": f"coacd threshold {threshold}", "pieces": len(pieces), "mesh_volume": float(mesh.volume),
                    "pieces_volume": vol, "volume_rel_error": abs(vol - mesh.volume) / mesh.volume}


def mass_properties(mesh, mass, scale):
    """Uniform-density mass properties of the (scaled) closed mesh in the object frame."""
    m = mesh.copy()
    m.apply_scale(scale)
    vol = m.volume
    m.density = mass / vol
    I = m.moment_inertia  # about the centre of mass, axes of the object frame
    return {"mass": mass, "com": m.center_mass.tolist(), "volume": vol,
            "fullinertia": [I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]}
