#!/usr/bin/python3
"""The CSPH moment matrix of every particle of a 3-D quarter-model snapshot
with its mirror images in the planes x = 0 and z = 0 (Wendland C2, the
pair-mean h), recomputed offline: how many pass the determinant guard
(1/1024; kernels/common.cl then, kernels/matrix.cl since session 35) with a smallest eigenvalue below a corner's
(1/8). dx is the SEBS d/dx 12 run's. Session 34; about 37 CPU-minutes
for 444,028 particles.

usage: csph_conditioning.py SNAPSHOT.h5
"""
import h5py, numpy as np, sys
from scipy.spatial import cKDTree
dx=1.0833e-6
f=h5py.File(sys.argv[1])
p=f['position'][:]; m=f['mass'][:]; rho=f['density'][:]; hs=f['smoothing_length'][:]; fl=f['flags'][:]
n=len(p)
P=[];M=[];R=[];H=[]
for sx in (1,-1):
  for sz in (1,-1):
    q=p.copy(); q[:,0]*=sx; q[:,2]*=sz
    P.append(q);M.append(m);R.append(rho);H.append(hs)
P=np.concatenate(P);V=np.concatenate(M)/np.concatenate(R);H=np.concatenate(H)
tree=cKDTree(P)
hmax=hs.max()
lam=np.empty(n); det=np.empty(n); nb=np.empty(n,int)
for i in range(n):
  js=np.array(tree.query_ball_point(p[i], 2*hmax))
  r=P[js]-p[i]; hh=0.5*(hs[i]+H[js]); d=np.linalg.norm(r,axis=1); q=d/hh
  sel=(q<2)&(d>0); r=r[sel]; d=d[sel]; q=q[sel]; hh=hh[sel]
  sig=21/(16*np.pi*hh**3); dW=sig*(-5*q)*(1-q/2)**3/hh
  g=(dW/d)[:,None]*r
  B=np.einsum('j,ja,jb->ab',V[js][sel],-r,g)
  det[i]=np.linalg.det(B); lam[i]=np.abs(np.linalg.eigvals(B)).min(); nb[i]=sel.sum()
ok=det>=1/1024
print('particles',n,'det>=1/1024:',ok.sum())
for t in (0.125,0.1,0.075,0.05):
  s=ok&(lam<t); print(f'pass det guard, lambda_min < {t}: {s.sum()}  (failed: {(s&((fl&8)>0)).sum()}, neighbours median {np.median(nb[s]) if s.any() else 0})')
print('det < 1/1024 (identity now):', (~ok).sum())
