base="$PWD/bouncelab-0.1"; mkdir -p "$base"                 # bouncelab 0.1, for the side-by-side predict run
git -C "$REPO" archive f2a4aab bouncelab | tar -x -C "$base"
cd "$REPO"
date -u "+%Y-%m-%d %H:%M UTC"; echo "$(nproc) cores: $(lscpu | sed -n 's/^Model name: *//p')"
python benchmarks/bench_fit.py
python benchmarks/bench_predict.py
python benchmarks/bench_predict.py --baseline "$base" --rounds 5
python benchmarks/bench_piecewise.py
