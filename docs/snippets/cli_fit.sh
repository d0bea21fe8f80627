bouncelab fit PennerFixed B --save penner_B.json
echo "exit code $?"
cat penner_B.json
bouncelab fit Rigid A --method structured --seed 3
echo "exit code $?"
bouncelab fit PiecewiseAffine B --json > piecewise_B.json
echo "exit code $?"
head -n 20 piecewise_B.json
