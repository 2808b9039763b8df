"""tools/bench/result_compare.py: every call has its own key (the diff pairs
calls by key), and each library entry point it is there for is reached."""
from pdtbench import result_compare as rc


def keys():
    out = [" ".join(a) for a in rc.tune_calls()]
    out += [" ".join(a) for a in rc.reduce_calls()]
    out += [" ".join(a) for a in rc.autotune_calls()]
    out += [f"identify {name} " + " ".join(extra)
            for name, _, _, _, extra in rc.identify_calls()]
    return out


def test_every_call_has_its_own_key():
    k = keys()
    assert len(k) == len(set(k))


def test_every_command_and_method_is_called():
    k = keys()
    for part in ("tune --rule zn", "--form pid", "--method skogestad", "--method sung",
                 "--model auto", "--method elms", "--method eiv", "--experiment relay",
                 "--experiment chirp", "--tune amigo:pid"):
        assert any(part in key for key in k), part
