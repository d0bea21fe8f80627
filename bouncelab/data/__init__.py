"""Campaigns: the container (:mod:`~.data.campaign`), the files it is read from and written to
(:mod:`~.data.io`), the campaigns shipped with the package (:mod:`~.data.embedded`), what every analysis
accepts as data (:mod:`~.data.inputs`) and the launcher settings inferred from landings
(:mod:`~.data.settings`).

This layer sits above the laws; the conventions, units and checks every layer shares are in
:mod:`bouncelab.core`.
"""
