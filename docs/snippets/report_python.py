import bouncelab as bl

report = bl.reproduce(["B"], out="report", figures=False, progress=False,
                      law_set=["Rigid", "PennerFixed", "PiecewiseAffine"], bootstrap=20)
print(report)
print(report.inputs["B"].units, "|", report.inputs["B"].settings)
sec = report.sections["B"]
print(list(sec.tables))
print(sec.tables["crossvalidation"].frame.round(4))
for campaign, what, why in report.left_out:
    print(f"not made: {what}: {why}")
print(sec.comparison.results["Rigid"].model)
print(f"{len(report.files)} files in {report.out.name}/; the notebook view: {len(report._repr_html_())} characters")
