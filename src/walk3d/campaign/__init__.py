"""Multi-start campaigns: many random starts of one prediction, run in parallel and ranked.

The paper ran hundreds of random starts and kept the converged ones with the lowest criterion.
:func:`run_campaign` does that on a Dask distributed cluster, storing each start the moment it
finishes (resumable, atomic per start); :func:`rank` reads the ranking back from the folder.
See :mod:`walk3d.campaign.store` for the folder layout.
"""

from walk3d.campaign.ranking import rank
from walk3d.campaign.runner import CampaignReport, run_campaign
from walk3d.campaign.store import CampaignMismatch

__all__ = ["CampaignMismatch", "CampaignReport", "rank", "run_campaign"]
