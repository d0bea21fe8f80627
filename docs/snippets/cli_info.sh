bouncelab info A
echo "exit code $?"
printf 'run,a_in,b_in,c_in,a_out,b_out,c_out\n7,20.1,-15.2,3000,9.5,5.1,1500\n7,19.8,-15.0,3050,9.7,5.0,1480\n' > mine.csv
bouncelab info mine.csv --velocity-unit m/s --spin-unit rpm \
  --columns '{"landing": ["a_in", "b_in", "c_in"], "liftoff": ["a_out", "b_out", "c_out"], "setting": "run"}'
echo "exit code $?"
printf 'vx0,vy0,w0,vxF,vyF,wF,vx0_err,vy0_err,w0_err\n20.1,-15.2,3000,9.5,5.1,1500,0.2,0.2,60\n19.8,-15.0,3050,9.7,5.0,1480,0.2,0.2,60\n' > sd.csv
bouncelab info sd.csv --velocity-unit m/s --spin-unit rpm
echo "exit code $?"
bouncelab info sd.csv --velocity-unit m/s --spin-unit rpm --intervals sd
echo "exit code $?"
