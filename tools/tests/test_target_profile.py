"""tools/target_profile.py: its reading of QEMU's log (blocks translated,
blocks executed) into instructions per function for each call, on a log
made by hand in the two formats QEMU writes (Arm and RISC-V)."""
import importlib.util
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("target_profile",
                                              ROOT / "tools" / "target_profile.py")
target_profile = importlib.util.module_from_spec(spec)
spec.loader.exec_module(target_profile)


class FakeSymbols:
    """main 0x100-0x1ff, fn 0x200-0x2ff, leaf 0x300-0x3ff."""

    def name(self, pc):
        return {1: "main", 2: "fn", 3: "leaf"}.get(pc >> 8, "?")


def block(start, count, riscv=False):
    lines = ["IN: name\n"] + (["Priv: 3; Virt: 0\n"] if riscv else [])
    lines += ["0x%08x:  00000000  nop\n" % (start + 2 * i) for i in range(count)]
    return lines + ["\n"]


def run(pc):
    return "Trace 0: 0x7f0000000100 [00000000/%08x/00000510/ff020200] name\n" % pc


def log(riscv=False):
    lines = []
    lines += block(0x100, 3, riscv)   # main, before the call
    lines += block(0x200, 4, riscv)   # fn's entry
    lines += block(0x300, 5, riscv)   # leaf
    lines += block(0x110, 2, riscv)   # main after the call: the return site
    lines += [run(0x100), run(0x200), run(0x300), run(0x300), run(0x110)]
    # A second call: the leaf once, and a block of the entry again.
    lines += [run(0x200), run(0x300), run(0x110), run(0x300)]
    return lines


def test_each_call_counts_its_functions_alone():
    for riscv in (False, True):
        calls = target_profile.count_calls(iter(log(riscv)), FakeSymbols(), 0x200, {0x110})
        assert [total for _, total in calls] == [4 + 2 * 5, 4 + 5]
        first, second = calls[0][0], calls[1][0]
        assert first == {"fn": 4, "leaf": 10}
        assert second == {"fn": 4, "leaf": 5}


def test_a_block_never_translated_counts_one_unknown_instruction():
    lines = block(0x200, 2) + [run(0x200), run(0x3f0), run(0x110)]
    calls = target_profile.count_calls(iter(lines), FakeSymbols(), 0x200, {0x110})
    assert calls[0][0] == {"fn": 2, "?": 1}


def test_each_run_counts_the_translation_current_when_it_ran():
    # The entry's block translated with 4 instructions, run, then cut to 1
    # (as QEMU does under -icount) and run again.
    lines = block(0x200, 4) + [run(0x200)] + block(0x200, 1) + [run(0x200), run(0x110)]
    calls = target_profile.count_calls(iter(lines), FakeSymbols(), 0x200, {0x110})
    assert calls[0][0] == {"fn": 5}


def test_a_run_is_matched_to_its_translation_by_its_host_address():
    # Two translations of the entry side by side (4 instructions at host
    # address A, 1 at B); runs of A after B's translation still count 4.
    def run_at(host, pc):
        return "Trace 0: %s [00000000/%08x/00000510/ff020200] name\n" % (host, pc)
    lines = (block(0x200, 4) + [run_at("0xa", 0x200)] + block(0x200, 1) +
             [run_at("0xb", 0x200), run_at("0xa", 0x200), run(0x110)])
    calls = target_profile.count_calls(iter(lines), FakeSymbols(), 0x200, {0x110})
    assert calls[0][0] == {"fn": 9}


def test_reading_stops_after_the_calls_asked_for():
    lines = log() + [run(0x200), run(0x110)]
    calls = target_profile.count_calls(iter(lines), FakeSymbols(), 0x200, {0x110}, 1)
    assert len(calls) == 1 and calls[0][1] == 14
