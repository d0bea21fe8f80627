bouncelab info A
echo "exit code $?"
printf 'run,a_in,b_in,c_in,a_out,b_out,c_out\n7,20.1,-15.2,3000,9.5,5.1,1500\n7,19.8,-15.0,3050,9.7,5.0,1480\n' > mine.csv
bouncelab info mine.csv --velocity-unit m/s --spin-unit rpm \
  --columns '{"landing": ["a_in", "b_in", "c_in"], "liftoff": ["a_out", "b_out", "c_out"], "setting": "run"}'
echo "exit code $?"
