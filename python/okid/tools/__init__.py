# SPDX-License-Identifier: Apache-2.0
"""Host tools of okid for its users: the FMU generator (okid-fmu), the stabilization diagram and the paper's plots."""
