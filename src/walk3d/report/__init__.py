"""``report.html``: one self-contained page per prediction or campaign (docs/report.md).

* :mod:`.norms`: normative bands from the measured data in ``../shared/data``;
* :mod:`.html`: the page's HTML pieces (inline CSS, data URIs);
* :mod:`.prediction_page`, :mod:`.campaign_page`: the two pages;
* :mod:`.writer`: which folder is which, and the atomic write (``walk3d report``).

Nothing is imported here, so that a prediction's page (:mod:`.prediction_page`) is made
without loading :mod:`walk3d.campaign` (and Dask with it).
"""
