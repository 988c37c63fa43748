// Must compile with core's flags: core headers alone (the control for the stray_* cases).
#include "core/deformer.h"
#include "core/registration.h"
int main() { return 0; }
