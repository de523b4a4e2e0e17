from uma.failure import Failure


def test_failure_tests_false_and_keeps_reason():
    failure = Failure("no face found in frame.png")
    assert not failure
    assert failure.reason == "no face found in frame.png"
    assert str(failure) == failure.reason
