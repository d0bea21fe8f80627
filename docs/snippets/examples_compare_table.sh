python "$REPO/examples/compare_laws.py" | sed -n '/^| r |/,/^| Delta omega/p'
