!> Hertz contact (DEM): the surface particles as spheres of diameter dp,
!> f = kn overlap^(3/2) along the pair's normal (Canelas et al. 2016 form),
!> damped as Tsuji et al. (1992) for a set restitution, with Coulomb friction.
module contact_hertz
   use errors, only: alloc_check
   use kinds, only: rp
   use constants, only: ndim
   use tensor, only: sym_outer, sym_quad
   use params, only: params_t
   use particles, only: particles_t
   use body_dynamics, only: body_t
   use contact_state, only: contact_t, key_index, store_pair, contact_note_dt
   use contact_pair, only: pair_force, pair_friction, pair_viscous, body_mass, restitution, tau_pair
   implicit none
   private
   public :: tsuji_table, hertz_gather, hertz_apply

contains

   !> Restitution of one Hertz contact with the damping of Tsuji et al.
   !> (1992), m d'' = -k d^(3/2) - alpha sqrt(m k) d^(1/4) d', force never
   !> pulling, for alpha on a grid. In the units m = k = 1 and an impact
   !> speed of 1 the rebound speed is e; e depends on alpha alone, not on
   !> the speed, the mass or the stiffness (the d^(1/4) damping is what makes
   !> it so), so one table serves every contact.
   subroutine tsuji_table(ct)
      type(contact_t), intent(inout) :: ct
      integer, parameter :: na = 400
      real(rp), parameter :: alpha_max = 15.0_rp, ddt = 2.0e-3_rp
      integer :: k, m
      real(rp) :: a, d, v, k1(2), k2(2), k3(2), k4(2)
      integer :: ist
      character(len=200) :: emsg
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (ct%tab_alpha(0:na), ct%tab_e(0:na), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'ct%tab_alpha, ct%tab_e in tsuji_table')
      do k = 0, na
         ! dense near alpha = 0, where e changes fastest
         a = alpha_max*(real(k, rp)/na)**2
         d = 0.0_rp
         v = 1.0_rp
         steps: do m = 1, 10000000
            k1 = rate(d, v)
            k2 = rate(d + 0.5_rp*ddt*k1(1), v + 0.5_rp*ddt*k1(2))
            k3 = rate(d + 0.5_rp*ddt*k2(1), v + 0.5_rp*ddt*k2(2))
            k4 = rate(d + ddt*k3(1), v + ddt*k3(2))
            d = d + ddt*(k1(1) + 2.0_rp*k2(1) + 2.0_rp*k3(1) + k4(1))/6.0_rp
            v = v + ddt*(k1(2) + 2.0_rp*k2(2) + 2.0_rp*k3(2) + k4(2))/6.0_rp
            if (d < 0.0_rp .and. v < 0.0_rp) exit steps
         end do steps
         ct%tab_alpha(k) = a
         ct%tab_e(k) = -v
      end do
   contains
      pure function rate(d, v) result(r)
         real(rp), intent(in) :: d, v
         real(rp) :: r(2)
         r(1) = v
         r(2) = 0.0_rp
         if (d > 0.0_rp) r(2) = -max(d**1.5_rp + a*d**0.25_rp*v, 0.0_rp)
      end function rate
   end subroutine tsuji_table

   !> Damping number alpha that gives restitution e (the table is monotone).
   pure real(rp) function tsuji_alpha(ct, e) result(a)
      type(contact_t), intent(in) :: ct
      real(rp), intent(in) :: e
      integer :: lo, hi, mid
      real(rp) :: w
      lo = 0
      hi = size(ct%tab_e) - 1
      if (e >= ct%tab_e(lo)) then
         a = 0.0_rp
         return
      end if
      if (e <= ct%tab_e(hi)) then
         a = ct%tab_alpha(hi)
         return
      end if
      do while (hi - lo > 1)                   ! tab_e falls with alpha
         mid = (lo + hi)/2
         if (ct%tab_e(mid) > e) then
            lo = mid
         else
            hi = mid
         end if
      end do
      w = (ct%tab_e(lo) - e)/(ct%tab_e(lo) - ct%tab_e(hi))
      a = (1.0_rp - w)*ct%tab_alpha(lo) + w*ct%tab_alpha(hi)
   end function tsuji_alpha

   !> First pass over the candidate pairs of the sweep: the overlapping
   !> pairs, and per pair of touching bodies the sums of sqrt(overlap) n and
   !> sqrt(overlap) n n^T, which give the contact's normal and its stiffness
   !> along it.
   subroutine hertz_gather(ct, prm, p, bodies)
      type(contact_t), intent(inout) :: ct
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      type(body_t), intent(in) :: bodies(:)
      integer :: m, i, j, bi, bj, k, c, napp(0:size(bodies))
      real(rp) :: d(ndim), r2, overlap, n(ndim), w, un, kn, dmax, dt_pair, dt1(0:size(bodies))
      napp = 0
      dt1 = huge(1.0_rp)
      do m = 1, ct%nc
         i = ct%cij(1, m); j = ct%cij(2, m); bi = ct%cij(3, m); bj = ct%cij(4, m)
         d = p%x(:, i) - p%x(:, j)
         r2 = d(1)**2
         do c = 2, ndim
            r2 = r2 + d(c)**2
         end do
         ! resolve the coming impact from before the first touch: its duration
         ! for one pair meeting at the approach speed un (Hertz) is
         ! 2.94 dmax/|un|, dmax = (5/4 M un^2/kn)^(2/5); take 40 steps or more
         un = dot_product(p%v(:, i) - p%v(:, j), d)/sqrt(r2)
         if (un < 0.0_rp) then
            kn = hertz_stiffness(bodies, bi, bj, prm%dp)
            dmax = (1.25_rp*body_mass(bodies, bi, bj)*un*un/kn)**0.4_rp
            dt_pair = 2.94_rp*dmax/(40.0_rp*abs(un))
            call contact_note_dt(ct, dt_pair, bi, bj)
            if (r2 < (1.5_rp*prm%dp)**2) then
               ! about to touch: counted for each of its two bodies
               napp([bi, bj]) = napp([bi, bj]) + 1
               dt1([bi, bj]) = min(dt1([bi, bj]), dt_pair)
            end if
         end if
         overlap = prm%dp - sqrt(r2)
         if (overlap <= 0.0_rp) cycle
         ct%max_penetration = max(ct%max_penetration, overlap)
         k = key_index(ct, p%body(i), p%body(j))
         n = d/sqrt(r2)
         w = sqrt(overlap)
         ct%kw(k) = ct%kw(k) + w
         ! oriented from the lower body id to the higher, whichever of the two
         ! particles the sweep calls i
         ct%kx(:, k) = ct%kx(:, k) + merge(w, -w, p%body(i) > p%body(j))*n
         ct%kt(:, k) = ct%kt(:, k) + w*sym_outer(n)
         call store_pair(ct, i, j, bi, bj, n, overlap, 0.0_rp, 0.0_rp, k)
      end do
      ! a face that meets a face meets in N pairs at once: N kn in parallel
      ! shorten the impact by N^(2/5) (dmax above with N kn); 40 steps of that
      do k = 1, size(bodies)
         if (napp(k) > 1) call contact_note_dt(ct, dt1(k)*real(napp(k), rp)**(-0.4_rp), k, k)
      end do
   end subroutine hertz_gather

   !> Second pass. The contact of two bodies is one damped spring along its
   !> normal N (the sqrt(overlap)-weighted mean of the pair normals): its
   !> tangent stiffness along N is S = sum 3/2 kn sqrt(overlap) (n.N)^2 and
   !> its damping along N is alpha sqrt(M S / (3/2)), Tsuji's form with
   !> alpha for the set restitution (tsuji_table). The damping is shared
   !> among the pairs in proportion to their stiffness 3/2 kn sqrt(overlap),
   !> so that a single pair along N gets Tsuji's damping exactly and pairs
   !> that meet at a slant (particles between two of the other row) damp
   !> the motion along N as much as they resist it.
   subroutine hertz_apply(ct, prm, p, bodies)
      type(contact_t), intent(inout) :: ct
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      type(body_t), intent(inout) :: bodies(:)
      integer :: m, i, j, bi, bj, k
      real(rp) :: overlap, n(ndim), ul, kn, gn, mc, fn, sk, sn, nn(ndim), vij(ndim)
      do m = 1, ct%np
         i = ct%pij(1, m); j = ct%pij(2, m); bi = ct%pb(1, m); bj = ct%pb(2, m)
         n = ct%pn(:, m); overlap = ct%pw(m); k = ct%pkey(m)
         vij = p%v(:, i) - p%v(:, j)
         ul = dot_product(vij, n)
         kn = hertz_stiffness(bodies, bi, bj, prm%dp)
         mc = body_mass(bodies, bi, bj)
         sk = 1.5_rp*kn*sqrt(overlap)
         nn = ct%kx(:, k)/max(norm2(ct%kx(:, k)), tiny(1.0_rp))
         sn = 1.5_rp*kn*max(sym_quad(ct%kt(:, k), nn), &
                            1.0e-3_rp*ct%kw(k))
         gn = tsuji_alpha(ct, restitution(bodies, bi, bj))*sqrt(mc/(1.5_rp*sn))*sk
         fn = max(kn*overlap**1.5_rp - gn*ul, 0.0_rp)
         call pair_viscous(ct, bodies, p, i, j, bi, bj, gn, n)
         call contact_note_dt(ct, 0.2_rp*sqrt(mc/(1.5_rp*kn*ct%kw(k))), bi, bj)
         call pair_force(bodies, p, i, j, bi, bj, fn*n, .true.)
         call pair_friction(ct, bodies, p, i, j, bi, bj, n, fn, vij, spread(0.0_rp, 1, ndim))
      end do
   end subroutine hertz_apply

   !> Hertz stiffness kn of two particles of diameter dp of bodies bi and bj:
   !> 4/3 sqrt(dp/4) / (tau_i + tau_j).
   pure real(rp) function hertz_stiffness(bodies, bi, bj, dp) result(kn)
      type(body_t), intent(in) :: bodies(:)
      integer, intent(in) :: bi, bj
      real(rp), intent(in) :: dp
      kn = 4.0_rp/(3.0_rp*tau_pair(bodies, bi, bj))*sqrt(0.25_rp*dp)
   end function hertz_stiffness
end module contact_hertz
