cd "$REPO"
date -u "+%Y-%m-%d %H:%M UTC"
python benchmarks/bench_algorithms.py --problems 200 --seed 5
