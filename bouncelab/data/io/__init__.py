"""Reading and writing bounce campaigns: CSV, TSV, text, Excel, MATLAB and netCDF.

:func:`load_campaign` turns a measurement file (one row per bounce) into a
campaign :class:`xarray.Dataset` in the paper's scaled units (see
:mod:`bouncelab.core.units` and :mod:`bouncelab.data.campaign`);
:func:`save_campaign` writes a campaign to netCDF so that :func:`load_campaign`
reads it back bit for bit.

Sources
-------
``"A"`` or ``"B"`` (a *string*, any case)
    The campaign embedded in the package (``bouncelab/data/files/campaign_A.nc``
    and ``campaign_B.nc``). Any other string, and any :class:`pathlib.Path`
    (so ``Path("A")`` is the file ``A``), is a file path.
A :class:`pandas.DataFrame`
    Read exactly as a file whose header is the column names; errors name the row label.
``.csv``, ``.tsv``, ``.txt``
    Text table, first non-blank line is the header (after title lines such as
    ``Bounce test 2026-03-14, turf B``, detected conservatively, or the 1-based
    line ``header_row=`` names). The delimiter is sniffed
    (tab, semicolon, comma, else runs of whitespace). Blank lines and lines
    starting with ``#`` or ``%`` are skipped, except a ``#`` line after the header
    shaped like a data row, which is refused (``#N/A`` is a missing value). Encoding UTF-8 (a BOM is fine), else
    Latin-1. With a semicolon, tab or whitespace delimiter a decimal comma
    (``1,5``) is accepted. In a whitespace-delimited file a header name must not
    contain spaces, except a bracketed unit (``vx0 [m/s]`` is fine).
``.xlsx`` (``.xls``)
    First sheet, or ``sheet=`` (name or 0-based index); the first non-empty row
    is the header. Needs ``openpyxl`` (``.xls``: ``xlrd``), both installed by
    ``pip install 'bouncelab[excel]'``; without it, a DataError says so.
``.mat`` (MATLAB v5/v7, not v7.3)
    Each numeric vector of length n is a column named after the variable; an
    (n, k) matrix ``M`` gives columns ``M_1`` ... ``M_k`` (rows are bounces); a
    cell array of strings is a text column (e.g. the setting); the fields of a
    struct (``S.vx0``) or of a 1 x n struct array (``table2struct(T)``) are
    columns named after the field (``S.vx0`` if two structs share the field
    name). MATLAB ``table`` objects cannot be read: save
    ``table2struct(T, 'ToScalar', true)`` instead.
``.nc``, ``.netcdf``
    A file written by :func:`save_campaign` (it has ``landing`` and ``liftoff``
    variables) is loaded as is, attributes included. Any other netCDF file is a
    table: each 1-D variable is a column (an (n, k) variable gives ``V_1`` ...
    ``V_k``).

Columns
-------
A file holds one row per bounce and, for landing (touch-down, subscript 0) and
lift-off (subscript F), the horizontal velocity ``xdot``, the vertical
velocity ``ydot`` and the spin ``omega``; optionally a launcher setting (test
condition) label and the half-widths of the 95 % prediction intervals.

With ``columns=None`` the columns are found from the synonyms in
:data:`COLUMN_SYNONYMS`. Names are compared after *normalisation*: lower case,
``ω`` read as ``omega`` and ``ẋ`` as ``xdot``, and everything but letters and
digits removed, so ``"X_dot 0"``, ``"xdot0"`` and ``"x-dot-0"`` are the same
name. A header may end in a unit, which is not part of the name:
``"vx0 [m/s]"``, ``"Vx0 (m/s)"``, ``"omega0_rpm"``, ``"spin (rev/min)"``,
``"vx0 m/s"``. A name is *stem* + *phase* or, for a phase of two or more
characters and a stem of two or more, *phase* + *stem* (``in_vx``, not
``i_vx``; ``w_in``, not ``in_w``) or *phase* + *stem* + *phase*:

==========  =================================================================
stem        ``xdot``: xdot, dx, dxdt, vx, velx, xvel, xvelocity, velocityx, u,
            ux, horizontalvelocity, horizontalspeed, hvel, vh, vhoriz,
            vhorizontal
            ``ydot``: ydot, dy, dydt, vy, vely, yvel, yvelocity, velocityy, v,
            uy, verticalvelocity, verticalspeed, vvel, vv, vvert, vvertical
            ``omega``: omega, w, om, spin, spinrate, angularvelocity, angvel,
            omegaz, wz
landing     0, i, in, inb, inbound, incoming, incident, impact, land, landing,
            pre, before, initial, init, touchdown, td
lift-off    f, 1, out, outb, outbound, outgoing, rebound, lift, liftoff, post,
            after, final, takeoff, lo
==========  =================================================================

so the landing ``xdot`` is found under ``xdot0``, ``x_dot_0``, ``vx0``,
``vx_in``, ``u0``, ``xdot_in``, ``inbound_vx``, ``Landing Vx [m/s]``,
``Inbound horizontal velocity (m/s)``..., the lift-off one under ``xdotF``,
``vxF``, ``vx_out``, ``vx1``, ``outbound_vx``..., the spins under ``omega0``,
``w0``, ``spin0``, ``spin_in``, ``omegaF``, ``wF``, ``spin_out``... The
prediction-interval half-widths are the same names followed (or preceded) by
``pi``, ``pi95``, ``hw``, ``halfwidth``, ``ci`` or ``ci95`` (``vx0_pi``); by
``sd``, ``std``, ``stdev``, ``stddev`` or ``sigma`` they are standard
deviations, multiplied by 1.96 to 95 % half-widths (``omegaF_sd``); by
``err``, ``error``, ``unc`` or ``uncertainty`` they could be either, and
``load_campaign(..., intervals="pi95" or "sd")`` must say which. They are
used only when all three of a state are present. The setting column is one of
``setting(s)``, ``setting_id``, ``setting_no``, ``setting_number``,
``launcher_setting(s)``, ``condition(s)``, ``condition_id``,
``test_condition(s)``, ``group``, ``group_id``, ``setup``, ``config``,
``configuration``, ``case``, ``test_case``; numeric labels become integers
(``"01"`` becomes 1), other labels stay strings. If a role matches no column
or several, :func:`load_campaign` raises a
:class:`~bouncelab.core.errors.DataError` that lists the file's columns and spells
out the ``columns=`` argument to pass. A typical file that needs no argument::

    Test condition,Vx0 (m/s),Vy0 (m/s),Spin0 (rpm),VxF (m/s),VyF (m/s),SpinF (rpm)
    1,20.1,-15.2,3000,9.5,5.1,1500
    1,19.8,-15.0,3050,9.7,5.0,1480

With ``columns=`` given, it maps roles to the file's names::

    load_campaign("bounces.csv", columns={
        "landing": ["Vx in", "Vy in", "Spin in"],      # xdot0, ydot0, omega0
        "liftoff": ["Vx out", "Vy out", "Spin out"],   # xdotF, ydotF, omegaF
        "setting": "Test",                              # optional
        "landing_pi": ["dVx in", "dVy in", "dSpin in"], # optional
        "liftoff_pi": ["dVx out", "dVy out", "dSpin out"],
    })

A landing or lift-off may be given as speed, angle and spin (launch-monitor
files): headers such as ``speed_in``, ``angle_in``, ``inbound speed``,
``landing angle``, ``launch angle`` are recognised when that is unambiguous, and
explicitly ``columns={"landing": {"speed": ..., "angle": ..., "spin": ...}}``.
The landing angle is positive below the horizontal, the lift-off angle above
it, in degrees unless the header or ``units={"angle": "rad"}`` says rad; speeds
are >= 0 with the ball moving in +x and spin > 0 is backspin (omega > 0).
Such a state's intervals may be half-widths of its speed, angle and spin
(``speed_in_pi``, ``angle_in_pi``, ``spin_in_pi``, or
``columns={"landing_pi": {"speed": ..., "angle": ..., "spin": ...}}``): they
are propagated to first order, with independent speed and angle errors, to the
xdot, ydot, omega half-widths the campaign holds
(:func:`~bouncelab.core.units.polar_halfwidths_to_cartesian`), and the attr
``interval_form`` says so. Half-widths are read in absolute units only: a
relative unit (``speed_in_pi (%)``, ``pct``, ``rel``) is refused. A mapping in
``columns=`` is trusted to say what each column holds; a list (xdot, ydot,
omega) naming recognised speed or angle columns is refused, and so is a
half-width column named as a state's, or the reverse.

Requested names are matched with the same tolerance (``"vx in"`` finds
``"VX_IN [m/s]"``); a name that matches two file columns is an error unless it
is spelled exactly as one of them. ``landing`` and ``liftoff`` are required;
only the roles listed are read.

Units
-----
Values are converted to scaled units (radii/s, rad/s) with the ball radius
``ball_radius_m``. The unit of a column is given by ``units=``
(``{"velocity": "m/s", "spin": "rpm"}``, either key optional, applying to the
prediction intervals too) and/or by the file: the unit at the end of the
column's header name or, failing that, a *units row* right under the header (a
row whose cells are units such as ``m/s``, ``rpm``). If both are given for a
column and disagree, the load fails; each column may have its own unit, and
the units read are recorded in the ``source_units`` attr. Known units are those of
:mod:`bouncelab.core.units` (velocity: m/s, ft/s, mph, km/h, radius/s = 1/s
= s^-1; spin: rad/s, rpm = rev/min = rot per min, rev/s = Hz, deg/s; ``1/s`` on a
spin column means rad/s; CF spellings such as ``m s-1`` too). With no unit, the
numbers are read in scaled units only if they are plausible in no other unit
(:mod:`bouncelab.core.plausibility`); otherwise the load fails and says which units
they fit and how to declare one. Whatever the units, values beyond
:data:`~bouncelab.core.plausibility.PLAUSIBLE_RANGES` are refused as a unit mistake.
Examples::

    load_campaign("bounces.csv", units={"velocity": "m/s", "spin": "rpm"})
    load_campaign("bounces.xlsx", sheet="Campaign B", units={"spin": "rev/s"})
    load_campaign("scaled.txt", units={"spin": "rad/s"})  # radii/s (the only fit), rad/s

A campaign netCDF file is already in scaled units: ``columns=`` and
``units=`` are refused, its stored ``ball_radius_m`` is kept, and
``campaign=``/``surface=`` replace the stored names only when given.

Errors
------
Every problem with the file is a :class:`~bouncelab.core.errors.DataError` whose
message names the file, the column as spelled in the file and the data row
(the first row under the header is row 1; blank and comment lines are not
counted, and the message also gives the line of a text file or the cell of a
spreadsheet). Nothing is written or kept when a load fails. With
``missing="drop"`` rows with a missing value in a column that is read are left
out instead, with a :class:`~bouncelab.core.errors.DroppedRowsWarning`.
"""

# COLUMN_SYNONYMS, and the synonym table's internals (``_role_of``...), which stay importable
# from here as when this package was one module.
from bouncelab.data.io.columns import _PHASES as _PHASES
from bouncelab.data.io.columns import _SETTING_NAMES as _SETTING_NAMES
from bouncelab.data.io.columns import _STATE_KEYS as _STATE_KEYS
from bouncelab.data.io.columns import _STEMS as _STEMS
from bouncelab.data.io.columns import COLUMN_SYNONYMS
from bouncelab.data.io.columns import _build_state_keys as _build_state_keys
from bouncelab.data.io.columns import _normalize as _normalize
from bouncelab.data.io.columns import _role_of as _role_of
from bouncelab.data.io.load import EMBEDDED_CAMPAIGNS, SUPPORTED_SUFFIXES, load_campaign
from bouncelab.data.io.save import save_campaign

__all__ = [
    "COLUMN_SYNONYMS",
    "EMBEDDED_CAMPAIGNS",
    "SUPPORTED_SUFFIXES",
    "load_campaign",
    "save_campaign",
]
