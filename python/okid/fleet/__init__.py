# SPDX-License-Identifier: Apache-2.0
"""okid.fleet: every record of many machines identified in parallel on Dask, modes tracked over time.

    from okid import fleet
    fleet.synthesize("fleet", fleet.FleetSpec(assets=8, records=24))
    fleet.identify_fleet(["fleet/records"], "modes.parquet", options={"order": 4})
    tracks, drift = fleet.track(fleet.read_modes("modes.parquet"))

Install with ``pip install .[fleet]`` (Dask distributed, pyarrow, pandas, matplotlib). The command
line is ``okid-fleet`` (okid.fleet.cli); docs/fleet.md has the rest.
"""
from .job import FleetError, Interrupted, Limits, Summary, identify_fleet, read_modes, records_done
from .records import ChannelSpec, RecordError, RecordRef, discover, read
from .rows import identify_record
from .synth import FleetSpec, synthesize
from . import monitor
from .track import TrackOptions, drift_summary, mac, track
from .track import alarms as track_alarms

__all__ = ["identify_fleet", "read_modes", "records_done", "Summary", "Limits", "FleetError", "Interrupted",
           "ChannelSpec", "RecordRef", "RecordError", "discover", "read", "identify_record",
           "FleetSpec", "synthesize", "track", "drift_summary", "track_alarms", "TrackOptions", "mac", "monitor"]
