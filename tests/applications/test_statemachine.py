import pytest

from applications.graph.loader import load_application
from applications.statemachine import StateMachine


def percepts(**values):
    base = {"people.count": 0, "people.new": 0, "user.present": False, "user.distance": None,
            "survey.done": False}
    base.update({k.replace("_", "."): v for k, v in values.items()})
    return base


def test_waits_30_s_before_creating_attention():
    machine = StateMachine(load_application("survey"), now=0.0)
    assert machine.step(percepts(people_new=1), now=29.9) is None
    fired = machine.step(percepts(people_new=1), now=30.1)
    assert (fired.source, fired.target) == ("Wait", "CreateAttention")
    assert machine.time_in_state(31.0) == pytest.approx(0.9)


def test_priorities_decide_when_two_ways_out_hold():
    machine = StateMachine(load_application("survey"), now=0.0)
    machine.step(percepts(people_new=1), now=31.0)
    # a person at 0.5 m after 16 s: both conditions hold, priority 1 (Interaction) wins
    fired = machine.step(percepts(user_present=True, user_distance=0.5), now=47.0)
    assert fired.target == "Interaction"


def test_absent_distance_makes_the_comparison_false():
    machine = StateMachine(load_application("survey"), now=0.0)
    machine.step(percepts(people_new=1), now=31.0)
    fired = machine.step(percepts(user_present=False, user_distance=None), now=32.0)
    assert fired.target == "Wait"


def test_replace_keeps_the_current_state_and_its_time():
    app = load_application("survey")
    machine = StateMachine(app, now=0.0)
    machine.step(percepts(people_new=1), now=31.0)
    assert machine.replace(load_application("survey"), now=35.0) is False
    assert machine.state.name == "CreateAttention" and machine.time_in_state(35.0) == 4.0
