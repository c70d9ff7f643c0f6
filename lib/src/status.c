/* SPDX-License-Identifier: Apache-2.0 */
/* Human-readable status and warning strings. */
#include "okid/status.h"

const char *okid_status_str(okid_status status)
{
    switch (status) {
    case OKID_OK: return "ok";
    case OKID_E_NULL_POINTER: return "a required pointer argument is NULL";
    case OKID_E_BAD_SIZE: return "a size or leading dimension is out of range";
    case OKID_E_BAD_ORDER: return "the model order does not fit the observer order or the Hankel size";
    case OKID_E_BAD_PARAMETER: return "a real parameter is out of range or not finite";
    case OKID_E_WORKSPACE_TOO_SMALL: return "the workspace is too small";
    case OKID_E_WORKSPACE_ALIGNMENT: return "the workspace is not aligned to OKID_WORKSPACE_ALIGN bytes";
    case OKID_E_NOT_INITIALIZED: return "the identifier is not initialised";
    case OKID_E_NONFINITE_SAMPLE: return "a sample is NaN or infinite and was rejected";
    case OKID_E_NOT_ENOUGH_DATA: return "not enough samples for the number of unknowns";
    case OKID_E_RANK_DEFICIENT: return "the data is rank deficient (input not persistently exciting, or order above the Hankel rank)";
    case OKID_E_DECOMPOSITION_FAILED: return "a matrix decomposition did not converge";
    case OKID_E_BACKEND_ARGUMENT: return "the linear-algebra backend rejected an argument (internal error)";
    case OKID_E_NOT_AVAILABLE: return "the requested result is not available";
    case OKID_E_DATA_RANGE: return "a channel's magnitude is outside the floating-point range the identification can use (rescale it, or use automatic scaling)";
    }
    return "unknown status";
}

const char *okid_warning_str(unsigned warning_bit)
{
    switch (warning_bit) {
    case OKID_W_REGRESSOR_RANK_DEFICIENT: return "regressor rank deficient (noise-free data or observer order above the minimum)";
    case OKID_W_UNSTABLE_POLE: return "an identified pole lies on or outside the unit circle";
    case OKID_W_NONPHYSICAL_POLE: return "an identified eigenvalue is real and non-positive (no continuous-time pole)";
    case OKID_W_ORDER_AT_LIMIT: return "the automatic order reached the largest order the Hankel matrix allows";
    case OKID_W_RANK_BELOW_MODEL: return "regressor rank below r(p+1)+n: the order exceeds what the data supports, or a mode is not excited";
    case OKID_W_WEAK_EXCITATION: return "the input is only weakly persistently exciting (ill-conditioned input regressor)";
    case OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM: return "(near) noise-free data with observer order p above the minimum ceil(n/m): observer Markov parameters not unique";
    case OKID_W_HANKEL_SPAN_SHORT: return "the Hankel span (alpha+beta)*dt is shorter than the slowest identified period";
    case OKID_W_REALIZATION_ILL_CONDITIONED: return "the realization is ill conditioned (sigma_1/sigma_n of the Hankel above 1/sqrt(eps))";
    case OKID_W_RESIDUAL_NOT_WHITE: return "a refined output's residual is not white (an unmeasured force, a drift or too low an order): its stds are the sandwich ones";
    case OKID_W_OUTPUT_NOT_EXPLAINED: return "the refined model explains less than half of an output (fit below 50 %: a drift, an offset, an unmodelled sensor)";
    case OKID_W_CORRELATION_FALLBACK: return "the correlation estimator's Cholesky guard refused: identified again with the QR fold";
    case OKID_W_RESIDUAL_INPUT_CORRELATED: return "a refined output's residual is correlated with an input (the model misses some of the input's dynamics: too low an order, a wrong D)";
    case OKID_W_NO_OUTPUT_EXPLAINED: return "the model explains less than half of every output (fit below 50 %: pure noise, or an input that does not drive the outputs)";
    case OKID_W_NO_PHYSICAL_MODE: return "the automatic selection found no physical mode (no pole stays put across the orders): no mode reported";
    case OKID_W_MODE_SPLIT: return "two refined pairs are one mode split in two (the same shape, frequencies not told apart): the order is higher than the record supports";
    default: return "unknown warning";
    }
}
