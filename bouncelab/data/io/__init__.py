"""Reading and writing bounce campaigns: CSV, TSV, text, Excel, MATLAB and netCDF files, and DataFrames.

:func:`load_campaign` turns a measurement file (one row per bounce) into a campaign
:class:`xarray.Dataset` in the paper's scaled units (:mod:`bouncelab.core.units`,
:mod:`bouncelab.data.campaign`); :func:`save_campaign` writes a campaign to netCDF so that
:func:`load_campaign` reads it back bit for bit. ``load_campaign("A")`` and ``"B"`` are the embedded
(synthetic) campaigns.

Each format is read by its library into one pandas DataFrame (:mod:`~bouncelab.data.io.read`:
``pandas.read_csv`` after the delimiter, title lines, a units row and comments are found,
``pandas.read_excel``, ``scipy.io.loadmat``, ``xarray.open_dataset``); one module,
:mod:`~bouncelab.data.io.interpret`, turns it into a campaign: the columns found from the synonyms of
:data:`COLUMN_SYNONYMS` (:mod:`~bouncelab.data.io.names`) or named by ``columns=``, Cartesian or
speed, angle and spin; units from ``units=``, the headers, a units row or a netCDF attribute, with
:mod:`bouncelab.core.plausibility` refusing numbers only a wrong unit makes; interval columns (95 %
half-widths or standard deviations); settings; missing values. Every problem is a
:class:`~bouncelab.core.errors.DataError` naming the file, the column as spelled in the file and the
data row (the first row under the header is row 1; the message gives the file's line or the
spreadsheet's cell), with the options that would put it right as hints. :mod:`~bouncelab.data.io.landings`
reads the landings of ``bouncelab predict --input`` the same way.

docs/data.md ("Loading your own files") describes the sources, the names recognised, the units and
every refusal in full.
"""

from bouncelab.data.io.load import EMBEDDED_CAMPAIGNS, SUPPORTED_SUFFIXES, load_campaign
from bouncelab.data.io.names import COLUMN_SYNONYMS
from bouncelab.data.io.save import save_campaign

__all__ = ["COLUMN_SYNONYMS", "EMBEDDED_CAMPAIGNS", "SUPPORTED_SUFFIXES", "load_campaign", "save_campaign"]
