"""Recordings (MCAP), their replay, and figures of trials."""
