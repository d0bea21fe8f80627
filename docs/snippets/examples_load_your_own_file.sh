python "$REPO/examples/load_your_own_file.py"
