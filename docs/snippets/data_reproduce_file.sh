python "$REPO/docs/snippets/data_paper_files.py" > /dev/null      # writes the stand-in campaign_A_measured.csv
bouncelab reproduce --data campaign_A_measured.csv --label A --velocity-unit m/s --spin-unit rpm --no-figures --quiet \
    --columns '{"landing": ["Vx in", "Vy in", "Spin in"], "liftoff": ["Vx out", "Vy out", "Spin out"], "setting": "Setting"}' \
    --out report
echo "exit code $?"
ls report/tables | head -n 4
sed -n '1,13p' report/tables/A_table3.md
