// SPDX-License-Identifier: Apache-2.0
// okid._core model functions: the chain model, the mechanical model's state space, the exact ZOH
// and the simulator of lib/include/okid/model.h. Matrices come in column-major (okid/_model.py
// converts), results go out as C-order numpy arrays.
#include <algorithm>

#include "binding.h"

#include <nanobind/stl/optional.h>

#include <optional>

namespace okid_py {

using FMatrix = nb::ndarray<const double, nb::ndim<2>, nb::f_contig, nb::device::cpu>;
using CVector = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using CBlock = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

// A column-major rows x cols buffer as a C-order (rows, cols) array.
static RealArray from_column_major(const std::vector<double> &v, int rows, int cols)
{
    okid_matrix view{v.data(), rows, cols, rows > 0 ? rows : 1};
    return matrix_array(view);
}

void bind_model(nb::module_ &m)
{
    m.def("chain_model", [](CVector masses, CVector dampers, CVector springs) {
        const int n2 = (int)masses.shape(0);
        if (dampers.shape(0) != masses.shape(0) + 1 || springs.shape(0) != masses.shape(0) + 1)
            return nb::make_tuple((int)OKID_E_BAD_SIZE, nb::none());
        std::vector<double> mm((size_t)n2 * n2), rr(mm.size()), kk(mm.size());
        const int s = okid_chain_model(n2, masses.data(), dampers.data(), springs.data(), mm.data(), rr.data(),
                                       kk.data());
        if (s != OKID_OK) return nb::make_tuple(s, nb::none());
        return nb::make_tuple(s, nb::make_tuple(from_column_major(mm, n2, n2), from_column_major(rr, n2, n2),
                                                from_column_major(kk, n2, n2)));
    });
    m.def("state_space", [](FMatrix mass, FMatrix damping, FMatrix stiffness, FMatrix input,
                            std::optional<FMatrix> acc, std::optional<FMatrix> vel, std::optional<FMatrix> disp,
                            int outputs) {
        const int n2 = (int)mass.shape(0), r = (int)input.shape(1), n = 2 * n2;
        okid_mechanical_model model{n2, r, outputs, mass.data(), damping.data(), stiffness.data(), input.data(),
                                    acc ? acc->data() : nullptr, vel ? vel->data() : nullptr,
                                    disp ? disp->data() : nullptr};
        std::vector<double> ac((size_t)n * n), bc((size_t)n * r), c((size_t)outputs * n), d((size_t)outputs * r);
        std::vector<double> work(OKID_STATE_SPACE_WORK_REALS(n2, r));
        const int s = okid_model_state_space(&model, ac.data(), bc.data(), c.data(), d.data(), work.data(), work.size());
        if (s != OKID_OK) return nb::make_tuple(s, nb::none());
        return nb::make_tuple(s, nb::make_tuple(from_column_major(ac, n, n), from_column_major(bc, n, r),
                                                from_column_major(c, outputs, n), from_column_major(d, outputs, r)));
    });
    m.def("discretize_zoh", [](FMatrix ac, FMatrix bc, double dt) {
        const int n = (int)ac.shape(0), r = (int)bc.shape(1);
        std::vector<double> a((size_t)n * n), b((size_t)n * r), work(OKID_ZOH_WORK_REALS(n, r));
        const int s = okid_discretize_zoh(n, r, ac.data(), bc.data(), dt, a.data(), b.data(), work.data(), work.size());
        if (s != OKID_OK) return nb::make_tuple(s, nb::none());
        return nb::make_tuple(s, nb::make_tuple(from_column_major(a, n, n), from_column_major(b, n, r)));
    });
    m.def("simulate", [](FMatrix a, FMatrix b, FMatrix c, FMatrix d, CBlock u, CVector x0) {
        const int n = (int)a.shape(0), r = (int)b.shape(1), mo = (int)c.shape(0);
        const size_t count = u.shape(0);
        std::vector<double> x((size_t)n), tmp((size_t)n), y(count * (size_t)mo);
        okid_simulator sim;
        int s = okid_simulator_init(&sim, n, r, mo, a.data(), b.data(), c.data(), d.data(), x.data(), tmp.data());
        if (s == OKID_OK) {
            std::copy(x0.data(), x0.data() + n, x.begin());  // after init, which zeroes the state

            nb::gil_scoped_release release;
            s = okid_simulate(&sim, count, u.data(), (size_t)r, y.data(), (size_t)mo);
        }
        if (s != OKID_OK) return nb::make_tuple(s, nb::none());
        const size_t nn = (size_t)n;
        return nb::make_tuple(s, nb::make_tuple(owned_array(std::move(y), {count, (size_t)mo}),
                                                owned_array(std::move(x), {nn})));
    });
    // okid_lift over the whole record: (status, (u_lifted (N / K, K r), y_lifted (N / K, m))).
    m.def("lift", [](CBlock u, CBlock y, int factor) {
        const int r = (int)u.shape(1), mo = (int)y.shape(1);
        const size_t count = u.shape(0), lifted_count = factor > 0 ? count / (size_t)factor : 0;
        if (y.shape(0) != count) return nb::make_tuple((int)OKID_E_BAD_SIZE, nb::none());
        std::vector<double> ul(lifted_count * (size_t)(factor > 0 ? factor : 1) * (size_t)r + 1),
            yl(lifted_count * (size_t)mo + 1);
        size_t lifted = 0;
        const int s = okid_lift(r, mo, factor, count, u.data(), (size_t)r, y.data(), (size_t)mo, ul.data(), yl.data(),
                                &lifted);
        if (s != OKID_OK) return nb::make_tuple(s, nb::none());
        ul.resize(lifted * (size_t)factor * (size_t)r);
        yl.resize(lifted * (size_t)mo);
        return nb::make_tuple(s, nb::make_tuple(owned_array(std::move(ul), {lifted, (size_t)factor * (size_t)r}),
                                                owned_array(std::move(yl), {lifted, (size_t)mo})));
    });
}

}  // namespace okid_py
