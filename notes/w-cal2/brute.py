import numpy as np, math
from scipy.special import logsumexp

def rigid(p, r, mu):
    """p (..., 3) landing; r, mu broadcast. returns (...,3) liftoff and regime code (1 slip fwd, 0 roll, -1 back)"""
    xd, yd, w = p[..., 0], p[..., 1], p[..., 2]
    k = mu * (1 + r)
    k = np.broadcast_to(k, np.broadcast_shapes(np.shape(k), np.shape(xd)))
    vp = xd + w
    thr = 3.5 * k * np.abs(yd)
    reg = np.where(vp > thr, 1, np.where(vp < -thr, -1, 0))
    s = reg.astype(float)
    xF = np.where(reg == 0, 5/7*xd - 2/7*w, xd + s*k*yd)
    wF = np.where(reg == 0, -5/7*xd + 2/7*w, w + 2.5*s*k*yd)
    yF = -r * yd
    xF, yF, wF = np.broadcast_arrays(xF, yF, wF)
    return np.stack([xF, yF, wF], -1), reg, k

def loglik_brute(post, x, land_mode="model", nmu=3500, nr=81, zmu_span=7.0, s_zero=True, return_per=False):
    """Exact (grid) marginal log likelihood of the two-level model with bounce scales s = 0.
    land_mode: 'model' -> post._land_cov (G held at the mode); 'exact' -> G in each grid point's regime."""
    nf = 2
    r_med, mu_med, sig_r, sig_mu = x[0], x[1], x[2], x[3]
    tau = x[6:9] if post.with_tau else np.zeros(3)
    tr_r, tr_mu = post.transforms["r"], post.transforms["mu"]
    zr0, zm0 = float(tr_r.forward(r_med)), float(tr_mu.forward(mu_med))
    base = tau**2 + post.jitter
    lv = post.liftoff_var if post.liftoff_var is not None else np.zeros((post.n, 3))
    lsd = post.landing_sd
    starts = list(post._starts) + [post.n]
    total = 0.0
    per = []
    umu = np.linspace(-zmu_span, zmu_span, nmu)
    for g in range(len(starts) - 1):
        a, b = starts[g], starts[g+1]
        p, y = post.p0[a:b], post.y[a:b]
        # local r range from ydot
        rhat = -(y[:, 1] @ p[:, 1]) / (p[:, 1] @ p[:, 1])
        sdy = math.sqrt(np.mean(lv[a:b, 1]) + base[1] + (0 if lsd is None else np.mean(lsd[a:b,1]**2)*rhat**2))
        sdr = sdy / math.sqrt(p[:, 1] @ p[:, 1])
        rlo, rhi = max(rhat - 12*sdr, 1e-6), min(rhat + 12*sdr, 1-1e-6)
        zlo, zhi = float(tr_r.forward(rlo)), float(tr_r.forward(rhi))
        zr = np.linspace(zlo, zhi, nr)
        vr = (zr - zr0) / sig_r
        vm = umu
        R = tr_r.inverse(zr)[:, None]            # (nr,1)
        M = tr_mu.inverse(zm0 + sig_mu * vm)[None, :]  # (1,nmu)
        logw = (-0.5*vr**2 - 0.5*math.log(2*math.pi) + math.log((zr[1]-zr[0])/sig_r))[:, None] + \
               (-0.5*vm**2 - 0.5*math.log(2*math.pi) + math.log(vm[1]-vm[0]))[None, :]
        ll = np.zeros((nr, nmu))
        for i in range(b - a):
            f, reg, k = rigid(p[i], R, M)   # (nr,nmu,3)
            res = y[i] - f
            if land_mode == "model" or lsd is None:
                if post._land_cov is None:
                    c = [np.full(ll.shape, lv[a+i, 0] + base[0]), np.full(ll.shape, lv[a+i,1]+base[1]),
                         np.full(ll.shape, lv[a+i,2]+base[2]), 0*ll, 0*ll, 0*ll]
                else:
                    lc = [q[0, a+i] if q.ndim == 2 else q[a+i] for q in post._land_cov]
                    c = [np.full(ll.shape, lv[a+i, 0] + base[0] + lc[0]), np.full(ll.shape, lv[a+i,1]+base[1]+lc[1]),
                         np.full(ll.shape, lv[a+i,2]+base[2]+lc[2]), np.full(ll.shape, lc[3]),
                         np.full(ll.shape, lc[4]), np.full(ll.shape, lc[5])]
            else:
                s2 = lsd[a+i]**2
                sg = reg.astype(float)
                rr = np.broadcast_to(R, ll.shape)
                roll = reg == 0
                # rows of G
                gx = np.stack([np.where(roll, 5/7, 1.0), np.where(roll, 0.0, sg*k), np.where(roll, -2/7, 0.0)], -1)
                gy = np.stack([0*ll, -rr, 0*ll], -1)
                gw = np.stack([np.where(roll, -5/7, 0.0), np.where(roll, 0.0, 2.5*sg*k), np.where(roll, 2/7, 1.0)], -1)
                dot = lambda u, v: (u*v*s2).sum(-1)
                c = [lv[a+i,0]+base[0]+dot(gx,gx), lv[a+i,1]+base[1]+dot(gy,gy), lv[a+i,2]+base[2]+dot(gw,gw),
                     dot(gx,gy), dot(gx,gw), dot(gy,gw)]
            A, Dd, F_, B, C, E = c
            # det & quad
            a1 = Dd*F_ - E*E; b1 = C*E - B*F_; c1 = B*E - C*Dd
            det = A*a1 + B*b1 + C*c1
            D2 = A*F_ - C*C; E2 = B*C - A*E; F2 = A*Dd - B*B
            xx, yy, zz = res[...,0], res[...,1], res[...,2]
            q = (a1*xx*xx + D2*yy*yy + F2*zz*zz + 2*(b1*xx*yy + c1*xx*zz + E2*yy*zz)) / det
            ll += -0.5*(np.log(det) + q + 3*math.log(2*math.pi))
        lg = logsumexp(ll + logw)
        per.append(lg)
        total += lg
    return (total, np.array(per)) if return_per else total
