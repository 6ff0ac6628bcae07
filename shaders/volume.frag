// Stencil only: colour writes are off in this pass.
void main() {}
