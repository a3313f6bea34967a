//! The chunked parallel scatter gives bitwise the serial pass's force vector and matrix.

use super::*;
use crate::prelude::*;
use crate::reference::sheet::{kevlar_sheet, sheet};

/// The assembly as it was before the parallel scatter: every force's local forces, then the
/// mass diagonal and every force's blocks, one element after the other (the reference
/// order).
fn serial_reference(
    a: &mut Assembler,
    model: &Model,
    input: &EvalInput<'_>,
    c: Coefficients,
) -> (Vec<f64>, Vec<f64>) {
    let (mut force, mut values) = (vec![0.0; model.n_dofs()], vec![0.0; a.nnz()]);
    for (f, blocks) in model.forces.iter().zip(a.blocks.iter_mut()) {
        f.evaluate(input, blocks);
    }
    for (fi, f) in model.forces.iter().enumerate() {
        let k = f.stencil_size();
        for (st, loc) in f.stencils().chunks(k).zip(a.blocks[fi].f.chunks(k)) {
            for (&d, &x) in st.iter().zip(loc) {
                force[d] += x;
            }
        }
    }
    for (r, &d) in a.dof_of.iter().enumerate() {
        values[a.diag[r]] += c.c_m * model.mass[d];
    }
    for (map, b) in a.maps.iter().zip(&a.blocks) {
        for (local, scale) in [(&b.dfdq, -c.c_q), (&b.dfdv, -c.c_v)] {
            for (&m, &x) in map.iter().zip(local.iter()) {
                if m != NONE {
                    values[m as usize] += scale * x;
                }
            }
        }
    }
    (force, values)
}

/// A crumpled, moving Kevlar sheet (springs, hinges, gravity, pressure drag, corner forces)
/// with triangle drag (non-symmetric ∂f/∂q and ∂f/∂v) and two clamped nodes.
fn shell_model(nx: usize, ny: usize) -> (Model, Vec<f64>, Vec<f64>) {
    let (mut model, state) = kevlar_sheet(nx, ny, 4.0, 3.0, 20.0);
    let s = sheet(nx, ny, 4.0, 3.0, 0.0);
    model.add_force(TriangleDrag::new(&s.tris, 1.2, 0.1, &Fluid::air()));
    model.fix_node(0);
    model.fix_node(nx * ny / 2);
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut noise = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let q: Vec<f64> = state.q.iter().map(|&x| x + 0.05 * noise()).collect();
    let v: Vec<f64> = (0..q.len()).map(|_| 5.0 * noise() - 2.0).collect();
    (model, q, v)
}

/// Evaluation with the Jacobian at `(q, v)`, t = 0.
fn jacobian_input<'a>(q: &'a [f64], v: &'a [f64]) -> EvalInput<'a> {
    EvalInput::outside_step(q, v, 0.0, true)
}

/// Implicit-Euler-like coefficients (dt = 1 ms).
const COEFFS: Coefficients = Coefficients {
    c_m: 1e6,
    c_q: 1.0,
    c_v: 1e3,
};

#[test]
fn chunked_scatter_is_bitwise_the_serial_order() {
    let (model, q, v) = shell_model(23, 17);
    let input = jacobian_input(&q, &v);
    let c = COEFFS;
    let (f_ref, v_ref) =
        serial_reference(&mut Assembler::with_chunks(&model, 1), &model, &input, c);
    assert!(v_ref.iter().any(|&x| x != 0.0) && f_ref.iter().all(|x| x.is_finite()));
    for n in [1, 2, 3, 7, plan::MAX_CHUNKS] {
        let mut a = Assembler::with_chunks(&model, n);
        // The cut really has `n` chunks (the test would not test the parallel path else).
        assert_eq!(a.val_chunks.len(), n);
        assert_eq!(a.dof_chunks.len(), n);
        let mut force = vec![f64::NAN; model.n_dofs()];
        let mut values = vec![f64::NAN; a.nnz()];
        a.assemble(&model, &input, &mut force, Some((&mut values, c)));
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert!(bits(&force) == bits(&f_ref), "force vector, {n} chunks");
        assert!(bits(&values) == bits(&v_ref), "matrix values, {n} chunks");
        // Without the Jacobian: the same force vector.
        let mut force2 = vec![f64::NAN; model.n_dofs()];
        a.assemble(&model, &input, &mut force2, None);
        assert!(
            bits(&force2) == bits(&f_ref),
            "force vector alone, {n} chunks"
        );
    }
}

#[test]
fn a_small_model_is_assembled_serially_to_the_same_bits() {
    let (model, q, v) = shell_model(9, 7);
    let input = jacobian_input(&q, &v);
    let c = COEFFS;
    let mut a = Assembler::new(&model);
    assert!(a.nnz() < SERIAL_BELOW && a.serial, "{} entries", a.nnz());
    assert!(a.blocks.iter().all(|b| b.serial));
    let (f_ref, v_ref) =
        serial_reference(&mut Assembler::with_chunks(&model, 3), &model, &input, c);
    let mut force = vec![f64::NAN; model.n_dofs()];
    let mut values = vec![f64::NAN; a.nnz()];
    a.assemble(&model, &input, &mut force, Some((&mut values, c)));
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert!(bits(&force) == bits(&f_ref) && bits(&values) == bits(&v_ref));
    // The large model of the test above stays in the pool.
    let (big, _, _) = shell_model(23, 17);
    let b = Assembler::new(&big);
    assert!(b.nnz() >= SERIAL_BELOW && !b.serial, "{} entries", b.nnz());
}
