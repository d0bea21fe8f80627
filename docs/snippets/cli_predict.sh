# The paper's published piecewise law for campaign A, on its typical driver landing (ft/s, deg, rev/s):
bouncelab predict PiecewiseAffine --published A --speed-angle-spin 93.6 37.3 34.9 --velocity-unit ft/s --spin-unit rev/s
echo "exit code $?"
# A law saved by 'bouncelab fit --save', on landings given as numbers and in a file (m/s and rpm):
bouncelab fit PennerFixed B --save penner_B.json > /dev/null
printf 'xdot0 ydot0 omega0\n20 -15 3000\n12 -6 -500\n' > landings.txt
bouncelab predict penner_B.json --landing 25 -10 6000 --input landings.txt --velocity-unit m/s --spin-unit rpm
echo "exit code $?"
# A launch monitor's shots, read by column name with the units row under the header; the lift-offs
# come out as speed, angle (above the horizontal) and spin, in the same units:
printf 'Shots 2026-03-14\nshot,spin,speed,angle\n,rpm,m/s,deg\n1,2094,28.5,37.3\n2,-500,10,60\n' > shots.csv
bouncelab predict penner_B.json --input shots.csv
echo "exit code $?"
# The same from standard input:
cat shots.csv | bouncelab predict penner_B.json --input - | tail -n 1
