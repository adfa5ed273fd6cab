#!/usr/bin/env python3
# Checks `dynid dynamics --robot puma560 [--drives] --json` against an independent implementation:
# Corke's standard-DH recursive Newton-Euler (world-free, COM-based recursion), written from
# ../shared/reference/puma560.md. Needs numpy (apt-get install python3-numpy).
# usage: tools/check_puma_independent.py build/bin/dynid
import numpy as np, json, subprocess, sys
pi=np.pi
dh=[(0,0,pi/2),(0,0.4318,0),(0.15005,0.0203,-pi/2),(0.4318,0,pi/2),(0,0,-pi/2),(0,0,0)]
m=[0,17.4,4.8,0.82,0.34,0.09]
r=[(0,0,0),(-0.3638,0.006,0.2275),(-0.0203,-0.0141,0.070),(0,0.019,0),(0,0,0),(0,0,0.032)]
I=[(0,0.35,0),(0.13,0.524,0.539),(0.066,0.086,0.0125),(1.8e-3,1.3e-3,1.8e-3),(0.3e-3,0.4e-3,0.3e-3),(0.15e-3,0.15e-3,0.04e-3)]
Jm=[200e-6]*3+[33e-6]*3; G=[-62.6111,107.815,-53.7063,76.0364,71.923,76.686]
B=[1.48e-3,.817e-3,1.38e-3,71.2e-6,82.6e-6,36.7e-6]
Tc=[(0.395,-0.435),(0.126,-0.071),(0.132,-0.105),(11.2e-3,-16.9e-3),(9.26e-3,-14.5e-3),(3.96e-3,-10.5e-3)]
def rne(q,qd,qdd,drives,grav=np.array([0,0,9.81])):
    n=6; z0=np.array([0,0,1.])
    w=np.zeros(3); wd=np.zeros(3); vd=grav.copy()  # base accel = +g up (gravity -z)
    Rs=[];ps=[];W=[];WD=[];VD=[];VC=[]
    for j in range(n):
        d,a,al=dh[j]; th=q[j]
        ct,st,ca,sa=np.cos(th),np.sin(th),np.cos(al),np.sin(al)
        R=np.array([[ct,-st*ca,st*sa],[st,ct*ca,-ct*sa],[0,sa,ca]])  # frame j in j-1
        p=np.array([a,d*sa,d*ca])  # origin of j in frame j coords (Corke's pstar)
        Rt=R.T
        wd=Rt@(wd+z0*qdd[j]+np.cross(w,z0*qd[j]))
        w=Rt@(w+z0*qd[j])
        vd=np.cross(wd,p)+np.cross(w,np.cross(w,p))+Rt@vd
        vc=np.cross(wd,r[j])+np.cross(w,np.cross(w,r[j]))+vd
        Rs.append(R);ps.append(p);W.append(w);WD.append(wd);VD.append(vd);VC.append(vc)
    f=np.zeros(3); nn=np.zeros(3); tau=np.zeros(n)
    for j in reversed(range(n)):
        Ic=np.diag(I[j]); F=m[j]*VC[j]; N=Ic@WD[j]+np.cross(W[j],Ic@W[j])
        if j<n-1:
            R=Rs[j+1]; nn=R@(nn+np.cross(R.T@ps[j],f))+np.cross(ps[j]+r[j],F)+N; f=R@f+F
        else:
            nn=np.cross(ps[j]+r[j],F)+N; f=F
        R=Rs[j]; tau[j]=nn@(R.T@z0)
        if drives:
            tau[j]+=G[j]**2*Jm[j]*qdd[j]+G[j]**2*B[j]*qd[j]+(abs(G[j])*Tc[j][0] if qd[j]>0 else (abs(G[j])*Tc[j][1] if qd[j]<0 else 0))
    return tau
def inertia(q,drives):
    return np.column_stack([rne(q,np.zeros(6),e,drives,np.zeros(3)) for e in np.eye(6)])
rng=np.random.default_rng(3); worst=0
for drives in (False,True):
  for k in range(20):
    q,qd,qdd=rng.uniform(-2,2,6),rng.uniform(-2,2,6),rng.uniform(-3,3,6)
    if k==0: q=np.array([0,pi/4,pi,0,pi/4,0]); qd=np.zeros(6); qdd=np.zeros(6)
    fmt=lambda v: ",".join(repr(float(x)) for x in v)
    out=json.loads(subprocess.check_output([sys.argv[1],"dynamics","--robot","puma560"]+(["--drives"] if drives else [])+["--q",fmt(q),"--dq",fmt(qd),"--ddq",fmt(qdd),"--json"]))
    t=rne(q,qd,qdd,drives); M=inertia(q,drives)
    e=max(np.abs(np.array(out["tau"])-t).max(), np.abs(np.array(out["M"])-M).max())
    worst=max(worst,e)
    if k==0: print("qn gravity", "drives" if drives else "rigid", t.round(6), "dynid", np.round(out["tau"],6))
print("max |dynid - independent| over tau and M, 40 states:", worst)
