"""Data and units: conventions, the campaign container, file loading, the published tables."""

from bouncelab.data import plausibility, published, units
from bouncelab.data.campaign import campaign_arrays, make_campaign, validate_campaign
from bouncelab.data.slip_roll import SLIP_ROLL_CLASSES, classify_slip_roll

__all__ = [
    "SLIP_ROLL_CLASSES",
    "campaign_arrays",
    "classify_slip_roll",
    "make_campaign",
    "plausibility",
    "published",
    "units",
    "validate_campaign",
]
