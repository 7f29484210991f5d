// A drawing module as a build of another ltca would leave it (tests/app/check_stale_module.py):
// the entry points of ltca_plots.so, its ABI text another version's. It draws nothing: ltca must
// refuse it before handing it a Figure.
extern "C" __attribute__((visibility("default"))) const char* ltca_plots_abi() {
  return "ltca 0.0.1, plots ABI 0, sizes 1/2/3/4/5";
}
extern "C" __attribute__((visibility("default"))) bool ltca_plots_has_device(const char*) { return true; }
extern "C" __attribute__((visibility("default"))) void ltca_plots_draw(const void*, const char*, const char*) {}
