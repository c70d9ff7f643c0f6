/* SPDX-License-Identifier: Apache-2.0 */
// Shared helpers of the okid._core binding: numpy arrays out of okid's column-major views, and the
// status a call returns to the Python layer (okid/_errors.py turns it into an exception).
#pragma once

// nanobind's headers call fprintf(stderr, ...) and count on <cstdio> arriving through other
// headers: with the stable ABI (Python.h without stdio.h) and LLVM's libc++ (scripts/wheel.sh) it
// does not, so it comes first here and in every file that includes nanobind before this one.
#include <cstdio>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <algorithm>
#include <atomic>
#include <complex>
#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

extern "C" {
#include "okid/okid.h"
}

namespace nb = nanobind;

namespace okid_py {

// A read-only numpy array that owns a copy of the data.
using RealArray = nb::ndarray<nb::numpy, const double>;
using ComplexArray = nb::ndarray<nb::numpy, const std::complex<double>>;

// Status of a call refused because another thread is using the same identifier.
constexpr int STATUS_BUSY = 1000;

// Refuses a second thread instead of letting two calls corrupt one identifier.
class UseGuard {
public:
    explicit UseGuard(std::atomic<bool> &busy) : busy_(busy), acquired_(!busy.exchange(true)) {}
    ~UseGuard()
    {
        if (acquired_) busy_.store(false);
    }
    bool acquired() const { return acquired_; }

private:
    std::atomic<bool> &busy_;
    bool acquired_;
};

template <class T> nb::ndarray<nb::numpy, const T> owned_array(std::vector<T> &&values, std::initializer_list<size_t> shape)
{
    auto *store = new std::vector<T>(std::move(values));
    nb::capsule owner(store, [](void *p) noexcept { delete static_cast<std::vector<T> *>(p); });
    return nb::ndarray<nb::numpy, const T>(store->data(), shape.size(), shape.begin(), owner);
}

// A column-major okid_matrix view as a (rows, cols) C-order numpy array (copied).
inline RealArray matrix_array(okid_matrix m)
{
    std::vector<double> v((size_t)m.rows * (size_t)m.cols);
    for (int i = 0; i < m.rows; ++i)
        for (int j = 0; j < m.cols; ++j) v[(size_t)i * (size_t)m.cols + (size_t)j] = (double)okid_matrix_at(m, i, j);
    return owned_array(std::move(v), {(size_t)m.rows, (size_t)m.cols});
}

inline RealArray vector_array(const okid_real *values, int count)
{
    std::vector<double> v(values, values + count);
    return owned_array(std::move(v), {(size_t)count});
}

inline ComplexArray complex_array(const okid_complex *values, int count)
{
    std::vector<std::complex<double>> v((size_t)count);
    for (int i = 0; i < count; ++i) v[(size_t)i] = {(double)values[i].re, (double)values[i].im};
    return owned_array(std::move(v), {(size_t)count});
}

// One mode as a dict of the okid_mode fields (m outputs).
nb::dict mode_dict(const okid_mode &md, int m);

// A physical mode of a selection over Hankel windows (okid.SelectedMode): its representative's
// okid_mode fields, its cluster's statistics, of_orders (the orders of its window's table), and
// its support (windows of of_windows).
nb::dict selected_mode_dict(const okid_selected_mode &s, int of_orders, int windows, int of_windows, int m);

// Text written by a C writer into memory (open_memstream), as a Python str.
template <class Writer> nb::str write_to_string(Writer &&write)
{
    char *text = nullptr;
    size_t size = 0;
    FILE *out = open_memstream(&text, &size);
    if (out == nullptr) throw std::bad_alloc();
    write(out);
    std::fclose(out);
    nb::str s(text, size);
    std::free(text);
    return s;
}

// An okid_config from the dict of its fields (okid/_config.py makes it).
okid_config config_from_dict(const nb::dict &d);
// The work a long call hands to the library between two looks at Python, in multiply-adds: some
// 10-50 ms (docs/python.md, "Long calls"), short enough for Ctrl-C, long enough to cost nothing.
constexpr double CHUNK_WORK = 67108864.0;  // 2^26

// Rows per chunk for a cost of work_per_row multiply-adds a row: 16384 for the paper's fold (a
// 63-wide factor), fewer for wider problems, at least 64.
inline size_t chunk_rows(double work_per_row)
{
    const double rows = CHUNK_WORK / (work_per_row > 1.0 ? work_per_row : 1.0);
    return rows < 64.0 ? 64 : rows > 16384.0 ? 16384 : (size_t)rows;
}

// Rows per chunk of okid_push_block: a row's fold costs about w^2 multiply-adds, w = r + (r + m) p + m
// the factor's width.
inline size_t push_chunk_rows(const okid_config &cfg)
{
    const double w = (double)cfg.num_inputs + (double)(cfg.num_inputs + cfg.num_outputs) * cfg.observer_order +
                     (double)cfg.num_outputs;
    return chunk_rows(w * w);
}

// feed(first, count) over rows [0, total) in chunks of `chunk` rows with the GIL released. Between
// chunks, with the GIL held, a pending signal raises (KeyboardInterrupt for Ctrl-C: nb::python_error)
// and progress(offset + done, grand_total) is called when progress is not None. feed returns an
// okid_status; OKID_E_NONFINITE_SAMPLE (rows rejected, the rest taken) does not stop the feed, any
// other failure does. Returns the first failure, else the last non-OK status, else OKID_OK.
template <class Feed>
int feed_in_chunks(size_t total, size_t chunk, const nb::object &progress, size_t offset, size_t grand_total,
                   Feed &&feed)
{
    int status = OKID_OK;
    for (size_t done = 0; done < total;) {
        const size_t count = std::min(chunk, total - done);
        int s;
        {
            nb::gil_scoped_release release;
            s = feed(done, count);
        }
        if (s != OKID_OK) status = s;
        if (s != OKID_OK && s != OKID_E_NONFINITE_SAMPLE) return s;
        done += count;
        if (PyErr_CheckSignals() != 0) throw nb::python_error();
        if (!progress.is_none()) progress(offset + done, grand_total);
    }
    return status;
}

// An IdentifierCore that takes over workspace (aligned_alloc) and the identifier over it (after its
// okid_identify() gave res), and the ResultCore of res: (IdentifierCore, ResultCore).
nb::tuple adopt_identifier(const okid_config &cfg, void *workspace, const okid_identifier &id, const okid_result &res);

void bind_identifier(nb::module_ &m);
void bind_host(nb::module_ &m);
void bind_model(nb::module_ &m);
void bind_refine(nb::module_ &m);
void bind_auto(nb::module_ &m);
void bind_ambient(nb::module_ &m);

}  // namespace okid_py
