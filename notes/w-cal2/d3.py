import sys; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from setup import *
from brute import rigid
from scipy.optimize import minimize
seed, iv = int(sys.argv[1]), sys.argv[2] == "1"
data, post, x0 = build(seed, iv)
import os; _f = f"/tmp/cal2/mode_{seed}_{iv}.npy"; mode = np.load(_f) if os.path.exists(_f) else np.r_[0.5, 0.4, 0.25, 0.3, 0, 0, 1e-3, 1e-3, 1e-3]
rng = np.random.default_rng(seed)  # realised draws as in spot_campaign
base = np.column_stack([rng.uniform(300, 1200, 100), rng.uniform(-700, -200, 100), rng.uniform(-300, 600, 100)])
_ = rng.normal(0.0, [15.0, 15.0, 30.0], (600, 3))
zr_true = S_R * rng.standard_normal(100); zm_true = S_MU * rng.standard_normal(100)
print("realised: mu geo-mean", MU_MED*np.exp(zm_true.mean()), "sd z_mu", zm_true.std(ddof=1), "r med", 1/(1+np.exp(-zr_true.mean())), "sd z_r", zr_true.std(ddof=1))
tau = np.zeros(3) if iv else np.array([float(a) for a in sys.argv[3].split(",")])
lv = post.liftoff_var if post.liftoff_var is not None else np.zeros((post.n, 3))
lsd = post.landing_sd
tr_r, tr_mu = post.transforms["r"], post.transforms["mu"]
zmu = np.linspace(-4.0, 1.5, 2751)
starts = list(post._starts) + [post.n]
E, ZR, MX = [], [], []
t = time.time()
for g in range(100):
    a, b = starts[g], starts[g+1]
    p, y = post.p0[a:b], post.y[a:b]
    rhat = -(y[:, 1] @ p[:, 1]) / (p[:, 1] @ p[:, 1])
    sdy = math.sqrt(np.mean(lv[a:b, 1]) + tau[1]**2 + 16 * rhat**2 + 1e-9)
    sdr = sdy / math.sqrt(p[:, 1] @ p[:, 1])
    zr = np.linspace(float(tr_r.forward(max(rhat - 12*sdr, 1e-6))), float(tr_r.forward(min(rhat + 12*sdr, 1-1e-6))), 81)
    R = tr_r.inverse(zr)[:, None]; M = np.exp(zmu)[None, :]
    ll = np.zeros((81, len(zmu)))
    for i in range(b - a):
        f, reg, k = rigid(p[i], R, M)
        res = y[i] - f
        roll = reg == 0; sg = reg.astype(float); rr = np.broadcast_to(R, ll.shape)
        s2 = SD_LAND**2 if lsd is None else lsd[a+i]**2   # no intervals: the landing error is still there physically
        gx = np.stack([np.where(roll, 5/7, 1.0), np.where(roll, 0.0, sg*k), np.where(roll, -2/7, 0.0)], -1)
        gy = np.stack([0*ll, -rr, 0*ll], -1)
        gw = np.stack([np.where(roll, -5/7, 0.0), np.where(roll, 0.0, 2.5*sg*k), np.where(roll, 2/7, 1.0)], -1)
        dot = lambda u, v: (u*v*s2).sum(-1)
        lvi = SD_LIFT**2 if post.liftoff_var is None else lv[a+i]
        A, Dd, F_, B, C, Ee = [lvi[0]+tau[0]**2+dot(gx,gx), lvi[1]+tau[1]**2+dot(gy,gy), lvi[2]+tau[2]**2+dot(gw,gw), dot(gx,gy), dot(gx,gw), dot(gy,gw)]
        a1 = Dd*F_ - Ee*Ee; b1 = C*Ee - B*F_; c1 = B*Ee - C*Dd
        det = A*a1 + B*b1 + C*c1
        D2 = A*F_ - C*C; E2 = B*C - A*Ee; F2 = A*Dd - B*B
        xx, yy, zz = res[...,0], res[...,1], res[...,2]
        q = (a1*xx*xx + D2*yy*yy + F2*zz*zz + 2*(b1*xx*yy + c1*xx*zz + E2*yy*zz)) / det
        ll += -0.5*(np.log(det) + q + 3*math.log(2*math.pi))
    mx = ll.max(); E.append(np.exp(ll - mx)); ZR.append(zr); MX.append(mx)
print("grid", time.time() - t)
dzm = zmu[1] - zmu[0]
def negll(th):
    mr, mm, lsr, lsm = th
    sr, sm = math.exp(lsr), math.exp(lsm)
    phm = np.exp(-0.5*((zmu - mm)/sm)**2) / (sm*math.sqrt(2*math.pi)) * dzm
    tot = 0.0
    for g in range(100):
        zr = ZR[g]
        phr = np.exp(-0.5*((zr - mr)/sr)**2) / (sr*math.sqrt(2*math.pi)) * (zr[1]-zr[0])
        v = phr @ E[g] @ phm
        tot += math.log(v) + MX[g] if v > 0 else -1e10
    return -tot
th0 = np.array([0.0, math.log(0.4), math.log(0.25), math.log(0.3)])
print("exact ll at truth", -negll(th0))
res = minimize(negll, th0, method="Nelder-Mead", options={"xatol": 1e-4, "fatol": 1e-3, "maxiter": 2000})
mr, mm, lsr, lsm = res.x
print("EXACT MLE (s=0, tau=%s): r %.4f mu %.4f (%.1f %%) sigma_r %.4f sigma_mu %.4f ll %.2f" % (tau, 1/(1+math.exp(-mr)), math.exp(mm), 100*(math.exp(mm)/0.4-1), math.exp(lsr), math.exp(lsm), -res.fun))
# Hermite restricted MLE, same space
if post.landing_sd is not None and mode is not None:
    post.fix_landing(mode)
def hneg(th):
    x = np.r_[1/(1+math.exp(-th[0])), math.exp(th[1]), math.exp(th[2]), math.exp(th[3]), 0, 0, np.maximum(tau, 1e-6)]
    return -post.log_likelihood(x)
res2 = minimize(hneg, th0, method="Nelder-Mead", options={"xatol": 1e-4, "fatol": 1e-3, "maxiter": 2000})
mr, mm, lsr, lsm = res2.x
print("HERMITE MLE (same): r %.4f mu %.4f (%.1f %%) sigma_r %.4f sigma_mu %.4f" % (1/(1+math.exp(-mr)), math.exp(mm), 100*(math.exp(mm)/0.4-1), math.exp(lsr), math.exp(lsm)))
print("exact ll at hermite MLE", -negll(res2.x), "vs at exact MLE", -res.fun)
