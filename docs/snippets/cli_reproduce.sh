bouncelab reproduce --campaign B --no-figures --quiet --out report
echo "exit code $?"
ls report report/laws
cat report/tables/B_table2.md
echo "----"
cat report/tables/B_bootstrap.md
echo "----"
cat report/tables/B_assessment.md
