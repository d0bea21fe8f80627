python "$REPO/examples/fit_campaign.py" | tail -n 22
