"""The reference solid of a finger link for `derive_fingers.py`: deterministic surface samples of its
mesh (`tri_samples`), the voxel solid with small through-holes filled, and distances to its surface
(`Surface`)."""
import numpy as np
import trimesh
from scipy import ndimage
from scipy.spatial import cKDTree

SURF_STEP = 0.0001     # surface sampling of the reference meshes (distance tree, voxel shell)
PITCH = 0.0002         # voxel pitch of the inside test


def tri_samples(T, step):
    """Points on the triangles T (n, 3, 3), deterministic, no point of a triangle farther than
    step / sqrt(2) from one: rows parallel to the longest edge, <= step apart, each sampled <= step
    apart (ends included, so the vertices are samples)."""
    T = np.asarray(T, float)
    if len(T) == 0:
        return np.zeros((0, 3))
    e = np.stack([np.linalg.norm(T[:, (i + 1) % 3] - T[:, i], axis=1) for i in range(3)], axis=1)
    k = np.argmax(e, axis=1)
    idx = (k[:, None] + np.arange(3)[None, :]) % 3            # longest edge P0 -> P1, P2 opposite
    T = np.take_along_axis(T, idx[:, :, None], axis=1)
    P0, P1, P2 = T[:, 0], T[:, 1], T[:, 2]
    Lb = np.linalg.norm(P1 - P0, axis=1)
    area2 = np.linalg.norm(np.cross(P1 - P0, P2 - P0), axis=1)
    h = np.where(Lb > 0, area2 / np.maximum(Lb, 1e-300), 0.0)
    nr = np.ceil(h / step).astype(int) + 1                    # rows (j = 0 .. nr-1; 1 row = the edge)
    tri = np.repeat(np.arange(len(T)), nr)
    j = np.arange(len(tri)) - np.repeat(np.cumsum(nr) - nr, nr)
    f = np.where(nr[tri] > 1, j / np.maximum(nr[tri] - 1, 1), 0.0)
    a = P0[tri] + f[:, None] * (P2[tri] - P0[tri])
    b = P1[tri] + f[:, None] * (P2[tri] - P1[tri])
    npt = np.ceil(Lb[tri] * (1 - f) / step).astype(int) + 1
    row = np.repeat(np.arange(len(tri)), npt)
    i = np.arange(len(row)) - np.repeat(np.cumsum(npt) - npt, npt)
    g = np.where(npt[row] > 1, i / np.maximum(npt[row] - 1, 1), 0.0)
    return a[row] + g[:, None] * (b[row] - a[row])


class Surface:
    """The reference solid of a link and distances to its surface. Voxels (PITCH) of the lattice samples
    (SURF_STEP) form the shell; dilated by one voxel and hole-filled, the solid. With `fill_radius`,
    small through-holes are filled too (pin bores at the joints, the follower's screw holes): in every
    voxel slice across x, y and z, the regions enclosed by the solid with area <= pi fill_radius^2.
    The dilated shell counts as outside (its points lie within ~0.4 mm of the surface). Distances:
    a Euclidean distance transform of the shell and hole-cap voxels, interpolated (searching, error
    <~0.2 mm), or the k-d tree of the surface samples and cap-voxel centres refined by exact closest
    points on the mesh (reporting)."""

    def __init__(self, mesh, fill_radius=0.0, step=SURF_STEP, pitch=PITCH):
        self.mesh = mesh
        S = np.unique(np.round(tri_samples(mesh.triangles, step), 9), axis=0)
        self.pitch = pitch
        self.lo = mesh.bounds[0] - 4 * pitch
        shape = np.ceil((mesh.bounds[1] + 4 * pitch - self.lo) / pitch).astype(int) + 1
        shell = np.zeros(shape, bool)
        ijk = np.floor((S - self.lo) / pitch).astype(int)
        shell[tuple(ijk.T)] = True
        thick = ndimage.binary_dilation(shell)
        solid = ndimage.binary_fill_holes(thick)
        fill = np.zeros(shape, bool)
        if fill_radius > 0:
            amax = np.pi * (fill_radius / pitch) ** 2
            for ax in range(3):
                for k in range(shape[ax]):
                    sl = np.take(solid, k, axis=ax)
                    holes = ndimage.binary_fill_holes(sl) & ~sl
                    if not holes.any():
                        continue
                    lab, n = ndimage.label(holes)
                    size = ndimage.sum(holes, lab, np.arange(1, n + 1))
                    keep = np.isin(lab, 1 + np.nonzero(size <= amax)[0])
                    idx = [slice(None)] * 3; idx[ax] = k
                    fill[tuple(idx)] |= keep
            fill &= ~solid
        full = solid | fill
        cap = fill & ndimage.binary_dilation(~full)
        C = self.lo + (np.argwhere(cap) + 0.5) * pitch
        self.fill = fill
        self.fill_volume = float(fill.sum() * pitch ** 3)
        self.fill_parts = int(ndimage.label(fill)[1]) if fill.any() else 0
        self.tree = cKDTree(np.vstack([S, C]))
        self.cap_tree = cKDTree(C) if len(C) else None
        self.edt = ndimage.distance_transform_edt(~(shell | cap), sampling=pitch)
        self.interior = full & ~thick

    def _vox(self, grid, X):
        ijk = np.floor((X - self.lo) / self.pitch).astype(int)
        ok = np.all((ijk >= 0) & (ijk < np.array(grid.shape)), axis=1)
        res = np.zeros(len(X), bool)
        res[ok] = grid[tuple(ijk[ok].T)]
        return res

    def inside(self, X):
        return self._vox(self.interior, X)

    def fast(self, X):
        """Approximate excess per point (distance transform; 0 inside)."""
        c = ((X - self.lo) / self.pitch - 0.5).T
        d = ndimage.map_coordinates(self.edt, c, order=1, mode="nearest")
        d[self.inside(X)] = 0.0
        return d

    def excess(self, X):
        """Per point: distance to the surface (k-d tree of the samples) if outside the solid, else 0."""
        d = np.zeros(len(X))
        out = ~self.inside(X)
        if out.any():
            d[out] = self.tree.query(X[out])[0]
        return d

    def exact(self, X):
        """Distance to the mesh if outside it (trimesh signed distance; exact), capped by the distance to
        the nearest hole-cap voxel centre; 0 inside the mesh or a filled hole."""
        if len(X) == 0:
            return np.zeros(0)
        sd = trimesh.proximity.signed_distance(self.mesh, X)   # > 0 inside
        d = np.maximum(-sd, 0.0)
        if self.cap_tree is not None:
            d = np.minimum(d, self.cap_tree.query(X)[0])
            d[self._vox(self.fill, X)] = 0.0
        return d

