/*
 * A test-only stand-in for Windows' bcryptprimitives.dll under Wine 8.0, which lacks it.
 * Rust's standard library (1.78 and later) imports ProcessPrng from it for HashMap's
 * random seeds, so without it the FMU's DLL does not load under Wine. Real Windows 10 and
 * later have the DLL; this one is only ever put next to the test driver, never in an FMU.
 * ProcessPrng fills the buffer with random bytes and always returns TRUE; the same
 * bytes come here from RtlGenRandom (advapi32's SystemFunction036), which Wine has.
 */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length) {
    while (length > 0) {
        ULONG chunk = length > 0x10000000 ? 0x10000000 : (ULONG)length;
        if (!SystemFunction036(data, chunk))
            return FALSE;
        data += chunk;
        length -= chunk;
    }
    return TRUE;
}
