printf 'Bounce test 2026-03-14, turf B\nv_a,a_a,w_a,v_b,a_b,w_b\n25.0,40.0,3000,12.0,20.0,1500\n24.6,39.5,NA,11.8,21.5,1480\n18.0,55.0,-1200,9.8,105.0,600\n' > lab.csv
bouncelab info lab.csv --velocity-unit m/s
echo "exit code $?"
bouncelab info lab.csv --velocity-unit m/s --spin-unit rpm --header-row 2 --missing drop \
  --columns '{"landing": {"speed": "v_a", "angle": "a_a", "spin": "w_a"}, "liftoff": {"speed": "v_b", "angle": "a_b", "spin": "w_b"}}'
echo "exit code $?"
