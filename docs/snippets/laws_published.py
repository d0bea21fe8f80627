import bouncelab as bl

for campaign in "AB":
    for cls in (bl.Rigid, bl.PennerVarying, bl.PennerFixed):
        print(campaign, cls.published(campaign))
    print(campaign, bl.PiecewiseAffine.published(campaign).plane_equation())
