#!/usr/bin/env python3
"""The 3-D Taylor face's largest particle radius (mm, centres: without the
face measure's dx/2) in 10-degree sectors about the
bar's axis (the quarter model's 0-90 degrees), on the last snapshot
(docs/validation_taylor.md, "Held face", 3-D copper).
Usage: face_sectors.py RUN..."""
import h5py, numpy as np, sys, glob, yaml
for d in sys.argv[1:]:
    dx=float(yaml.safe_load(open(d+'/case.resolved.yaml'))['numerics']['dx'])
    f=sorted(glob.glob(d+'/snap_*.h5'))[-1]
    h=h5py.File(f,'r'); pos=h['position'][...]
    x,y,z=pos[:,0],pos[:,1],pos[:,2]; r=np.hypot(x,y); th=np.degrees(np.arctan2(y,x))
    sel=z<z.min()+0.5*dx
    out=[]
    for a0 in range(0,90,10):
        s=sel&(th>=a0)&(th<a0+10)
        out.append('%d-%d:%.2f'%(a0,a0+10,r[s].max()*1e3 if s.any() else 0))
    print(d,' '.join(out))
