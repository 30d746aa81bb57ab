"""A stream's throttle in simulated time, which may go back (sim/sampling.py)."""

from sim.sampling import SLACK_S, due


def test_a_sample_is_due_once_a_period_has_passed_give_or_take_half_a_control_period():
    assert due(None, 5.0, 0.1)  # nothing sent yet
    assert not due(1.0, 1.0, 0.1)  # the same sample
    assert not due(1.0, 1.05, 0.1)
    assert due(1.0, 1.1 - SLACK_S, 0.1)
    assert not due(1.0, 1.1 - 2 * SLACK_S, 0.1)
    assert due(1.0, 1.001, 0.0)  # throttle 0: every new sample


def test_a_time_earlier_than_the_last_sample_s_is_a_new_trial_due_at_once():
    assert due(40.0, 0.001, 0.1)  # the world was reset at 40 s: the new trial's first sample goes out
    assert due(0.2, 0.0, 10.0)  # however long the period
    assert not due(0.001, 0.05, 0.1)  # then the period holds again in the new trial
