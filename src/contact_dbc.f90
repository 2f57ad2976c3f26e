!> Contact by the dynamic boundary (the baseline the seed paper compares
!> with): the surface particles of two bodies, or of a body and a wall, are
!> treated as the fluid treats them, continuity and pressure, with Coulomb
!> friction on the pressure force.
module contact_dbc
   use kinds, only: rp
   use constants, only: ndim
   use params, only: params_t
   use particles, only: particles_t
   use body_dynamics, only: body_t
   use kernel, only: kernel_gradw
   use contact_state, only: contact_t
   use contact_pair, only: pair_force, pair_friction
   implicit none
   private
   public :: dbc_pairs

contains

   !> Every candidate pair of the sweep: density rates into drho, the
   !> pressure force and its friction into the bodies.
   subroutine dbc_pairs(ct, prm, p, bodies, drho)
      type(contact_t), intent(inout) :: ct
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      type(body_t), intent(inout) :: bodies(:)
      real(rp), intent(inout) :: drho(:)
      integer :: m, i, j, bi, bj
      real(rp) :: d(ndim), gw(ndim), dr, f(ndim), fn, vij(ndim)
      do m = 1, ct%nc
         i = ct%cij(1, m); j = ct%cij(2, m); bi = ct%cij(3, m); bj = ct%cij(4, m)
         d = p%x(:, i) - p%x(:, j)
         vij = p%v(:, i) - p%v(:, j)
         gw = kernel_gradw(prm%kernel, d, prm%h)
         dr = dot_product(vij, gw)
         drho(i) = drho(i) + p%mass(j)*dr
         drho(j) = drho(j) + p%mass(i)*dr
         f = -p%mass(i)*p%mass(j)*(p%p(i) + p%p(j))/(p%rho(i)*p%rho(j))*gw
         fn = norm2(f)
         call pair_force(bodies, p, i, j, bi, bj, f, .true.)
         if (fn > 0.0_rp) call pair_friction(ct, bodies, p, i, j, bi, bj, f/fn, fn, vij, spread(0.0_rp, 1, ndim))
      end do
   end subroutine dbc_pairs
end module contact_dbc
