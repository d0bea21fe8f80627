python "$REPO/examples/trajectory_with_bounce.py"
echo "----"
python "$REPO/examples/trajectory_with_bounce.py" --law PiecewiseAffine --published --max-bounces 6 | tail -n 9
