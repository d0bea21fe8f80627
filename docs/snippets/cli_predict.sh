# The paper's published piecewise law for campaign A, on its typical driver landing (ft/s, deg, rev/s):
bouncelab predict PiecewiseAffine --published A --speed-angle-spin 93.6 37.3 34.9 --velocity-unit ft/s --spin-unit rev/s
echo "exit code $?"
# A law saved by 'bouncelab fit --save', on landings given as numbers and in a file (m/s and rpm):
bouncelab fit PennerFixed B --save penner_B.json > /dev/null
printf 'xdot0 ydot0 omega0\n20 -15 3000\n12 -6 -500\n' > landings.txt
bouncelab predict penner_B.json --landing 25 -10 6000 --input landings.txt --velocity-unit m/s --spin-unit rpm
echo "exit code $?"
