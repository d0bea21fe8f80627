"""Reading and writing bounce campaigns: CSV, TSV, text, Excel, MATLAB and netCDF files, and DataFrames.

:func:`load_campaign` turns a measurement file (one row per bounce) into a campaign :class:`xarray.Dataset` in
the paper's scaled units; :func:`save_campaign` writes one to netCDF that loads back bit for bit; ``"A"`` and
``"B"`` are the embedded (synthetic) campaigns. Each format is a backend (:mod:`~bouncelab.data.io.read`) that
returns one :class:`~bouncelab.data.io.read.Table`; one pipeline of small functions
(:mod:`~bouncelab.data.io.interpret`) reads it: columns by the synonyms of :data:`COLUMN_SYNONYMS` or
``columns=``, units, missing values, and every refusal a :class:`~bouncelab.core.errors.DataError` naming the
file, the column and the row. :mod:`~bouncelab.data.io.landings` (``bouncelab predict --input``) and
:func:`bouncelab.data.shots.load_shots` ask the same pipeline for their columns. docs/data.md describes it all.
"""

from bouncelab.data.io.load import EMBEDDED_CAMPAIGNS, SUPPORTED_SUFFIXES, load_campaign
from bouncelab.data.io.names import COLUMN_SYNONYMS
from bouncelab.data.io.save import save_campaign

__all__ = ["COLUMN_SYNONYMS", "EMBEDDED_CAMPAIGNS", "SUPPORTED_SUFFIXES", "load_campaign", "save_campaign"]
