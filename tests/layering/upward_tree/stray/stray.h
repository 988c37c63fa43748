// A folder that is not in CORE_LAYERS.
#pragma once
