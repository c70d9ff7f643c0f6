/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file okid.h
 * \brief Everything of the okid library: include this one header.
 */
#ifndef OKID_OKID_H
#define OKID_OKID_H

#include "okid/ambient.h"
#include "okid/identifier.h"
#include "okid/lifting.h"
#include "okid/limits.h"
#include "okid/modal.h"
#include "okid/modal_indicators.h"
#include "okid/mode_selection.h"
#include "okid/model.h"
#include "okid/random.h"
#include "okid/refine.h"
#include "okid/stabilization.h"
#include "okid/status.h"
#include "okid/types.h"

/** Library version. */
#define OKID_VERSION_MAJOR 0
#define OKID_VERSION_MINOR 1
#define OKID_VERSION_PATCH 0
#define OKID_VERSION_STRING "0.1.0"

#endif
