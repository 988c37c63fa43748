// The binding file (.cwb): the registration table, cached so deformation needs no rebind.
//
// Little-endian binary. Header: magic "CWBIND01", u32 format version (2 or 3), then the parameters
// (f64 local, f64 epsilon, u32 K, f64 scale, f64 max_distance, f64 close_distance, u8 variant),
// f64 h, f64 origin[3], u32 num_points, u32 num_cage_vertices, then arrays, each as u64 count + data:
// rest_cage (f32 x 3), elements (u32 x 3), element_status (u8), offsets (u32), ids (u32),
// weights (f32), bary (f32), rigid_points (u32), rigid_element (u32), rigid_bary (f32),
// and the report: u32 quality_inside, u32 max_set_size, u64 total_set_size.
// Version 2 appends: u8 separate, u32 separation_steps, u8 separation_applied, then set_offsets (u32),
// set_ids (u32), set_weights (f32) (the extended variant's contributing sets; empty otherwise) and
// separated (u32 per point, empty without separation). Version 1 files still load (no sets:
// Binding::has_sets() is false for an extended one; separate = false). Version 3 (written only for a
// binding to a parametric driver's samples, a project's driver cache; a cage's binding stays version 2) appends
// u32 num_samples and invalid_samples (u32, ascending: the degenerate samples, Binding::invalid_elements).
#pragma once

#include <string>

#include "core/deform/binding.h"
#include "core/deform/binding_check.h"

namespace cagewrap {

// The file's bytes.
std::string binding_bytes(const Binding& binding);
// Written atomically (core/base/atomic_write.h).
Status save_binding(const std::string& path, const Binding& binding);
// Validates every count against the file size, then the binding with validate_binding; every error
// names the file (and the table, entry and index where there is one).
Result<Binding> load_binding(const std::string& path);


}  // namespace cagewrap
