python "$REPO/examples/compare_laws.py" | tail -n 7
