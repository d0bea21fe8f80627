import sys; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from setup import *
for seed, iv in [(3, True), (1, False)]:
    t=time.time()
    data, post, x0 = build(seed, iv)
    mode = H._mode(post, x0)
    post.fix_landing(mode)
    mode = H._mode(post, mode)
    np.set_printoptions(precision=4, suppress=True, linewidth=150)
    print(seed, iv, post.columns)
    print("mode", mode, post(mode), time.time()-t)
    truth = np.r_[R_MED, MU_MED, S_R, S_MU, 1e-4, 1e-4, 1e-3, 1e-3, 1e-3]
    print("truth ll", post.log_likelihood(truth), "mode ll", post.log_likelihood(mode))
    np.save(f"/tmp/cal2/mode_{seed}_{iv}.npy", mode)
