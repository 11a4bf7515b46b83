/* Preloaded into every process of the sanitizer job (scripts/sanitize.sh, docs/testing.md).
 *
 * dlclose() that keeps the library loaded. Mesa's GLX front end dlcloses its DRI driver
 * (swrast_dri.so, llvmpipe) when the X display closes; memory the driver still holds in its
 * globals then looks leaked to LeakSanitizer, whose report can neither name the unmapped
 * library nor be matched by a suppression. With libraries kept loaded, that memory stays
 * reachable and every allocation stack stays symbolizable, so what is left is matched by
 * library name in tests/sanitizers/lsan.supp. The project itself never calls dlclose. */
int dlclose(void *handle)
{
    (void)handle;
    return 0;
}
