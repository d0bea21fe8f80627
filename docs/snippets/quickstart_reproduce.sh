bouncelab reproduce --out report
echo "exit code $?"
ls report report/tables | head -20
