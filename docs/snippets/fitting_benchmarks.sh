cd "$REPO"
date -u "+%Y-%m-%d %H:%M UTC"; echo "$(nproc) cores: $(lscpu | sed -n 's/^Model name: *//p')"
python benchmarks/bench_fit.py
python benchmarks/bench_predict.py
