"""The comparison of regenerated test vectors with the committed ones
(vectorgen._emit.vectors_differ): last digits and cancellation residues
pass, a changed generator does not."""
from vectorgen._emit import vectors_differ


def test_last_digits_agree():
    assert vectors_differ("a[] = {0.12622889648306374, 1.0};",
                          "a[] = {0.12622889648306376, 1.0};") is None


def test_cancellation_residue_beside_unit_coefficients_agrees():
    # a coefficient that is 0 in exact arithmetic, as two CPUs' libm left it
    assert vectors_differ("a[] = {-0.44932897100792163, -4.336808689942018e-19};",
                          "a[] = {-0.44932897100792163, -3.5032773546501543e-19};") is None


def test_small_values_of_a_small_array_are_compared():
    assert vectors_differ("a[] = {1e-22, 4.3e-19};", "a[] = {1e-22, 3.5e-19};") is not None


def test_changed_values_and_text_differ():
    assert vectors_differ("a[] = {1.0, 4.3e-19};", "a[] = {1.0, 3.5e-12};") is not None
    assert vectors_differ("a[] = {1.0, 2.0};", "a[] = {1.0, 2.1};") is not None
    assert vectors_differ("n = 2; a[] = {1.0};", "n = 3; a[] = {1.0};") is not None
    assert vectors_differ("a[] = {1.0};", "b[] = {1.0};") is not None
