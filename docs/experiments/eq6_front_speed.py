"""Why `reconstruct --paper` keeps the arrest distance δ (issue #40, item 1).

A 2-D model of kim-machiraju-thompson Eq. 6, φ_t = d(x)|∇φ|, with the
redistancing of Eq. 11 done exactly (each node set to its distance from the
front's crossings of the grid edges), on a circle of radius 1 that the front
approaches from 5h outside. Four schemes:

- ``paper``: the speed at each node is d at the node (what Eq. 6 says on a
  grid); every node is redistanced.
- ``paper_freeze``: the same, with the nodes next to the front left as they are
  by the redistancing, so that it cannot move the zero level.
- ``front``: the speed at each node is the exact d at its nearest front point
  (an extension velocity: the front moves at its own speed d(Γ), as Eq. 4
  says); every node is redistanced.
- ``front_freeze``: both.

The data are the circle itself (d = 0 on all of it) or samples of it at a given
spacing (in h). Prints the worst distance of the front from the circle and the
deepest point inside it (negative), in h, at steps 10 to 200.

Measured (2026-11-29, N = 96, h = 0.0316):

- continuous circle: ``paper`` 5.1h inside at step 100; ``front`` holds to 0.03h
  at step 100 and is 8.3h inside at 200; ``paper_freeze`` is 4.5h inside at 100;
  ``front_freeze`` holds within 0.012h for 200 steps.
- samples 0.5h, 1h and 2h apart, ``front_freeze``: 3.7h, 7.9h and 11.5h inside
  at step 100. The only zeros of d are the samples: between them the front
  meets d > 0 and goes on, so no scheme holds it there.

Every input of `reconstruct` is sampled (points, lattice particles), so the
arrest stays; the exact front speed with a zero-level-preserving redistancing
would let δ go only for data whose distance vanishes on a whole surface.

Run: ``python3 docs/experiments/eq6_front_speed.py [scheme] [N] [spacing]``
(numpy and scipy; spacing 0 = the continuous circle).
"""

import sys

import numpy as np
from scipy.spatial import cKDTree

SCHEMES = ("paper", "paper_freeze", "front", "front_freeze")


def run(scheme, n=96, spacing=0.0, steps=200, report=(10, 20, 30, 60, 100, 200)):
    half = 1.5
    h = 2 * half / (n - 1)
    axis = np.linspace(-half, half, n)
    x, y = np.meshgrid(axis, axis, indexing="ij")
    nodes = np.c_[x.ravel(), y.ravel()]
    radius, gamma = 1.0, 6 * h
    if spacing > 0:
        count = int(2 * np.pi * radius / (spacing * h))
        theta = np.arange(count) * 2 * np.pi / count
        samples = cKDTree(np.c_[radius * np.cos(theta), radius * np.sin(theta)])

        def distance(p):
            return samples.query(p)[0]
    else:

        def distance(p):
            return np.abs(np.hypot(p[:, 0], p[:, 1]) - radius)

    d_nodes = distance(nodes).reshape(x.shape)
    phi = np.hypot(x, y) - (radius + 5 * h)

    def crossings(f):
        found = []
        for ax in (0, 1):
            a, b = f, np.roll(f, -1, axis=ax)
            cut = a * b < 0
            if ax == 0:
                cut[-1, :] = False
            else:
                cut[:, -1] = False
            i, j = np.nonzero(cut)
            t = a[i, j] / (a[i, j] - b[i, j])
            found.append(np.c_[x[i, j] + (t * h if ax == 0 else 0), y[i, j] + (t * h if ax == 1 else 0)])
        return np.vstack(found)

    def next_to_front(f):
        s = np.sign(f)
        near = np.zeros_like(f, dtype=bool)
        for ax in (0, 1):
            for shift in (1, -1):
                near |= s * np.roll(s, shift, axis=ax) <= 0
        return near

    def inward_gradient(f):
        # Godunov's upwind |∇φ| for φ_t = F|∇φ| with F ≥ 0.
        dxm = (f - np.roll(f, 1, 0)) / h
        dxp = (np.roll(f, -1, 0) - f) / h
        dym = (f - np.roll(f, 1, 1)) / h
        dyp = (np.roll(f, -1, 1) - f) / h
        return np.sqrt(
            np.minimum(dxm, 0) ** 2 + np.maximum(dxp, 0) ** 2 + np.minimum(dym, 0) ** 2 + np.maximum(dyp, 0) ** 2
        )

    rows = []
    for step in range(1, steps + 1):
        tube = np.abs(phi) < gamma
        if not tube.any():
            rows.append((step, float("nan"), float("nan")))
            break
        dt = 0.5 * h / d_nodes[tube].max()
        frozen = next_to_front(phi) if scheme.endswith("freeze") else None
        if scheme.startswith("front"):
            front = crossings(phi)
            nearest = cKDTree(front).query(nodes)[1]
            speed = distance(front[nearest]).reshape(x.shape)
        else:
            speed = d_nodes
        phi = phi + dt * speed * inward_gradient(phi)
        front = crossings(phi)
        redistanced = np.sign(phi) * cKDTree(front).query(nodes)[0].reshape(x.shape)
        redistanced = np.clip(redistanced, -gamma, gamma)
        if frozen is not None:
            redistanced[frozen] = phi[frozen]
        phi = redistanced
        if step in report:
            r = np.hypot(*crossings(phi).T) - radius
            rows.append((step, np.abs(r).max() / h, r.min() / h))
    return rows


if __name__ == "__main__":
    schemes = [sys.argv[1]] if len(sys.argv) > 1 else SCHEMES
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 96
    spacing = float(sys.argv[3]) if len(sys.argv) > 3 else 0.0
    for scheme in schemes:
        for step, worst, deepest in run(scheme, n, spacing):
            print(f"{scheme:13s} step {step:3d}: worst {worst:7.3f}h, deepest {deepest:7.3f}h")
