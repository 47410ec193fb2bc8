#!/usr/bin/env python3
"""The 3-D Taylor face layer's neighbour stencil (docs/design_asph.md, "How
it would be judged"): for the particles that started in the lowest layer of
a 3-D quarter run (held face: mirror images across x = 0, y = 0 and z = 0),
their neighbours within the support 2h, split into those that started in
the same layer, by the direction of their initial offset (within 22.5
degrees of the lattice's x or y axis, or of its diagonals), and those from
other layers; means over the rim (outer 30% by radius) and the rest.

Usage: face_stencil.py RUN SNAPSHOT_INDEX...
"""
import sys

import h5py
import numpy as np
from scipy.spatial import cKDTree

run = sys.argv[1]
for k in map(int, sys.argv[2:]):
    f=h5py.File(f'{run}/snap_{k:05d}.h5'); x=f['position'][...].astype(float); u=f['displacement'][...]; h=f['smoothing_length'][...]
    x0=x-u; z0=x0[:,2]; lv=np.unique(np.round(z0,9)); face=np.abs(z0-lv[0])<1e-9
    # all particles with mirror images across x=0, y=0, z=0
    imgs=[np.array([a,b,c]) for a in (1,-1) for b in (1,-1) for c in (1,-1)]
    X=np.vstack([x*m for m in imgs]); X0=np.vstack([x0*m for m in imgs]); t=cKDTree(X)
    r=np.hypot(x[:,0],x[:,1]); rf=r[face]; rim=rf>np.percentile(rf,70)
    res={'rim':[], 'inner':[]}
    for idx,i in enumerate(np.flatnonzero(face)):
        js=[j for j in t.query_ball_point(x[i], 2*h[i]) if np.linalg.norm(X[j]-x[i])>0]
        d0=X0[js]-x0[i]   # initial offsets: which lattice neighbour each is
        inplane=np.abs(d0[:,2])<1e-9+0.5*(lv[1]-lv[0])  # same initial layer
        ang=np.degrees(np.arctan2(np.abs(d0[inplane,1]),np.abs(d0[inplane,0])))
        axis=np.sum((ang<22.5)|(ang>67.5)); diag=np.sum((ang>=22.5)&(ang<=67.5))
        res['rim' if rim[idx] else 'inner'].append((axis,diag,np.sum(~inplane)))
    for key,v in res.items():
        v=np.array(v); print(f'snap {k} {key:5s}: in-layer neighbours along the initial lattice axes {v[:,0].mean():.1f}, along its diagonals {v[:,1].mean():.1f}; from other layers {v[:,2].mean():.1f}')
