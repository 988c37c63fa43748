// Must compile with core's flags: core headers alone (the control for the stray_* cases).
#include "core/deform/deformer.h"
#include "core/deform/registration.h"
int main() { return 0; }
