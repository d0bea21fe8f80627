# Regenerate the reference-shot suite (table, Markdown, plot) and compare with the checked-in table.
python -m bouncelab.ground.shots --write .
diff "$REPO/docs/ground/reference_shots.csv" ground/reference_shots.csv && echo "no change to the reference shots"
head -3 ground/reference_shots.csv
